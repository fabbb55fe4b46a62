#include "chromatag/families/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace chromatag {
namespace {

// Linear sRGB -> XYZ (D65), from the IEC 61966-2-1 primaries
// (x, y) = R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06) and the white.
// Row sums equal kD65White.
constexpr double kRgbToXyz[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                    {0.2126729, 0.7151522, 0.0721750},
                                    {0.0193339, 0.1191920, 0.9503041}};
// Its inverse.
constexpr double kXyzToRgb[3][3] = {{3.2404542, -1.5371385, -0.4985314},
                                    {-0.9692660, 1.8760108, 0.0415560},
                                    {0.0556434, -0.2040259, 1.0572252}};

// CIE 1976 constants in their exact rational form: epsilon = (6/29)^3,
// kappa = (29/3)^3.
constexpr double kEpsilon = 216.0 / 24389.0;
constexpr double kKappa = 24389.0 / 27.0;

double LabF(double t) { return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0; }

double LabFInverse(double f) {
  const double f3 = f * f * f;
  return f3 > kEpsilon ? f3 : (116.0 * f - 16.0) / kKappa;
}

double Degrees(double radians) { return radians * 180.0 / kPi; }
double Radians(double degrees) { return degrees * kPi / 180.0; }

// Hue angle in degrees in [0, 360); 0 when a = b = 0 (Sharma et al., eq. 4).
double HueDegrees(double a, double b) {
  if (a == 0.0 && b == 0.0) return 0.0;
  double h = Degrees(std::atan2(b, a));
  return h < 0.0 ? h + 360.0 : h;
}

}  // namespace

double SrgbToLinear(double encoded) {
  const double v = std::fabs(encoded);
  const double linear = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  return std::copysign(linear, encoded);
}

double Srgb8ToLinear(uint8_t encoded) {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = SrgbToLinear(i / 255.0);
    return t;
  }();
  return table[encoded];
}

double LinearToSrgb(double linear) {
  const double v = std::fabs(linear);
  const double encoded = v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return std::copysign(encoded, linear);
}

Rgb SrgbToLinear(const Rgb& encoded) {
  return {SrgbToLinear(encoded.r), SrgbToLinear(encoded.g), SrgbToLinear(encoded.b)};
}

Rgb LinearToSrgb(const Rgb& linear) {
  return {LinearToSrgb(linear.r), LinearToSrgb(linear.g), LinearToSrgb(linear.b)};
}

Xyz LinearRgbToXyz(const Rgb& c) {
  const auto& m = kRgbToXyz;
  return {m[0][0] * c.r + m[0][1] * c.g + m[0][2] * c.b,
          m[1][0] * c.r + m[1][1] * c.g + m[1][2] * c.b,
          m[2][0] * c.r + m[2][1] * c.g + m[2][2] * c.b};
}

Rgb XyzToLinearRgb(const Xyz& c) {
  const auto& m = kXyzToRgb;
  return {m[0][0] * c.X + m[0][1] * c.Y + m[0][2] * c.Z,
          m[1][0] * c.X + m[1][1] * c.Y + m[1][2] * c.Z,
          m[2][0] * c.X + m[2][1] * c.Y + m[2][2] * c.Z};
}

Lab XyzToLab(const Xyz& xyz) {
  const double fx = LabF(xyz.X / kD65White.X);
  const double fy = LabF(xyz.Y / kD65White.Y);
  const double fz = LabF(xyz.Z / kD65White.Z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Xyz LabToXyz(const Lab& lab) {
  const double fy = (lab.L + 16.0) / 116.0;
  const double fx = fy + lab.a / 500.0;
  const double fz = fy - lab.b / 200.0;
  return {kD65White.X * LabFInverse(fx), kD65White.Y * LabFInverse(fy),
          kD65White.Z * LabFInverse(fz)};
}

Lab SrgbToLab(const Rgb& encoded) { return XyzToLab(LinearRgbToXyz(SrgbToLinear(encoded))); }

Lab SrgbToLab(const Rgb8& rgb) { return SrgbToLab(ToRgb(rgb)); }

Rgb LabToSrgb(const Lab& lab) { return LinearToSrgb(XyzToLinearRgb(LabToXyz(lab))); }

bool InSrgbGamut(const Lab& lab, double tolerance) {
  const Rgb c = XyzToLinearRgb(LabToXyz(lab));
  for (double v : {c.r, c.g, c.b}) {
    if (v < -tolerance || v > 1.0 + tolerance) return false;
  }
  return true;
}

Rgb8 ToRgb8(const Rgb& encoded) {
  auto to8 = [](double v) {
    return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
  };
  return {to8(encoded.r), to8(encoded.g), to8(encoded.b)};
}

Rgb ToRgb(const Rgb8& rgb) { return {rgb.r / 255.0, rgb.g / 255.0, rgb.b / 255.0}; }

Rgb8 LabToSrgb8(const Lab& lab) { return ToRgb8(LabToSrgb(lab)); }

std::string ToHex(const Rgb8& rgb) {
  char buffer[8];
  std::snprintf(buffer, sizeof(buffer), "#%02x%02x%02x", rgb.r, rgb.g, rgb.b);
  return buffer;
}

double Ciede2000(const Lab& lab1, const Lab& lab2, double kL, double kC, double kH) {
  // Step 1: a* is stretched near the neutral axis (G), giving C' and h'.
  const double c_ab = 0.5 * (std::hypot(lab1.a, lab1.b) + std::hypot(lab2.a, lab2.b));
  const double c_ab7 = std::pow(c_ab, 7.0);
  const double pow25_7 = 6103515625.0;  // 25^7
  const double g = 0.5 * (1.0 - std::sqrt(c_ab7 / (c_ab7 + pow25_7)));
  const double a1 = (1.0 + g) * lab1.a;
  const double a2 = (1.0 + g) * lab2.a;
  const double c1 = std::hypot(a1, lab1.b);
  const double c2 = std::hypot(a2, lab2.b);
  const double h1 = HueDegrees(a1, lab1.b);
  const double h2 = HueDegrees(a2, lab2.b);

  // Step 2: differences. The hue difference is zero when either chroma is.
  const double delta_l = lab2.L - lab1.L;
  const double delta_c = c2 - c1;
  double delta_h_deg = 0.0;
  if (c1 * c2 != 0.0) {
    delta_h_deg = h2 - h1;
    if (delta_h_deg > 180.0) delta_h_deg -= 360.0;
    if (delta_h_deg < -180.0) delta_h_deg += 360.0;
  }
  const double delta_h = 2.0 * std::sqrt(c1 * c2) * std::sin(Radians(delta_h_deg / 2.0));

  // Step 3: weighting functions around the means.
  const double l_mean = 0.5 * (lab1.L + lab2.L);
  const double c_mean = 0.5 * (c1 + c2);
  double h_mean = h1 + h2;
  if (c1 * c2 != 0.0) {
    if (std::fabs(h1 - h2) <= 180.0) {
      h_mean *= 0.5;
    } else {
      h_mean = h_mean < 360.0 ? 0.5 * (h_mean + 360.0) : 0.5 * (h_mean - 360.0);
    }
  }
  const double t =
      1.0 - 0.17 * std::cos(Radians(h_mean - 30.0)) + 0.24 * std::cos(Radians(2.0 * h_mean)) +
      0.32 * std::cos(Radians(3.0 * h_mean + 6.0)) - 0.20 * std::cos(Radians(4.0 * h_mean - 63.0));
  const double delta_theta = 30.0 * std::exp(-std::pow((h_mean - 275.0) / 25.0, 2.0));
  const double c_mean7 = std::pow(c_mean, 7.0);
  const double r_c = 2.0 * std::sqrt(c_mean7 / (c_mean7 + pow25_7));
  const double l50 = (l_mean - 50.0) * (l_mean - 50.0);
  const double s_l = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
  const double s_c = 1.0 + 0.045 * c_mean;
  const double s_h = 1.0 + 0.015 * c_mean * t;
  const double r_t = -std::sin(Radians(2.0 * delta_theta)) * r_c;

  const double dl = delta_l / (kL * s_l);
  const double dc = delta_c / (kC * s_c);
  const double dh = delta_h / (kH * s_h);
  return std::sqrt(dl * dl + dc * dc + dh * dh + r_t * dc * dh);
}

}  // namespace chromatag
