// Colour maths shared by the generator, the detector and the calibration tool.
//
// Spec section 5: CIELAB with the D65 white (0.95047, 1, 1.08883), reached from
// 8-bit sRGB through the IEC 61966-2-1 transfer curve and matrix; L* in
// [0, 100], signed a* and b*. This is true CIELAB, not OpenCV's 8-bit Lab.
#ifndef CHROMATAG_FAMILIES_COLOR_H_
#define CHROMATAG_FAMILIES_COLOR_H_

#include <cstdint>
#include <string>

namespace chromatag {

// CIELAB D65: L* in [0, 100], a* and b* signed, roughly [-128, 128].
struct Lab {
  double L = 0.0;
  double a = 0.0;
  double b = 0.0;
};

// CIE XYZ scaled so that the D65 white has Y = 1.
struct Xyz {
  double X = 0.0;
  double Y = 0.0;
  double Z = 0.0;
};

// Non-linear (gamma-encoded) or linear RGB with channels in [0, 1]. Which of
// the two is meant is said by the function that takes or returns it.
struct Rgb {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
};

// 8-bit gamma-encoded sRGB, as stored in image files and PDFs.
struct Rgb8 {
  uint8_t r = 0;
  uint8_t g = 0;
  uint8_t b = 0;
  bool operator==(const Rgb8& other) const { return r == other.r && g == other.g && b == other.b; }
};

// The D65 reference white of spec section 5.
inline constexpr Xyz kD65White{0.95047, 1.0, 1.08883};

// Pi, the toolkit's one definition (C++17 has no std::numbers).
inline constexpr double kPi = 3.14159265358979323846;

// IEC 61966-2-1 transfer curve, one channel in [0, 1] (values outside are
// extended symmetrically so that out-of-gamut colours round-trip).
double SrgbToLinear(double encoded);
double LinearToSrgb(double linear);

Rgb SrgbToLinear(const Rgb& encoded);
Rgb LinearToSrgb(const Rgb& linear);

// The same for an 8-bit value, from a table of all 256 (for reading pixels).
double Srgb8ToLinear(uint8_t encoded);

// Linear sRGB <-> XYZ. The matrix is derived from the IEC 61966-2-1 primaries
// and the D65 white at full precision, so that RGB white maps exactly to
// kD65White (the standard's 4-decimal rounding would leave white at b* = -0.01).
Xyz LinearRgbToXyz(const Rgb& linear);
Rgb XyzToLinearRgb(const Xyz& xyz);

Lab XyzToLab(const Xyz& xyz);
Xyz LabToXyz(const Lab& lab);

// Convenience chains.
Lab SrgbToLab(const Rgb& encoded);
Lab SrgbToLab(const Rgb8& rgb);
Rgb LabToSrgb(const Lab& lab);  // May fall outside [0, 1] when out of gamut.

// True if `lab` is inside the sRGB gamut: every linear channel within
// [-tolerance, 1 + tolerance].
bool InSrgbGamut(const Lab& lab, double tolerance = 1e-3);

// Rounds to 8-bit sRGB, clipping out-of-gamut channels.
Rgb8 LabToSrgb8(const Lab& lab);
Rgb8 ToRgb8(const Rgb& encoded);
Rgb ToRgb(const Rgb8& rgb);

// "#rrggbb".
std::string ToHex(const Rgb8& rgb);

// CIEDE2000 colour difference (CIE 142-2001), with the parametric weights kL,
// kC, kH (1 for the reference conditions). Implements the formula as written
// in Sharma, Wu and Dalal, Color Res. Appl. 30(1), 2005, including their notes
// on the mean hue and hue difference when a chroma is zero.
double Ciede2000(const Lab& lab1, const Lab& lab2, double kL = 1.0, double kC = 1.0,
                 double kH = 1.0);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_COLOR_H_
