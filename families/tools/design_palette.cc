// Reproduces the search behind palettes/default.json; see docs/palettes.md.
//
// Spec section 6 asks for: all colours inside sRGB, a* equal in each colour,
// a*(red) - a*(green) >= 80, b* shade gaps >= 35, the four chromatic L* within
// 5, black L* <= 10, white L* >= 95. This tool keeps every 8-bit channel inside
// [kInset, 255 - kInset] (printers reproduce less than sRGB; staying off the
// gamut's faces leaves room for the calibration tool to push colours outwards)
// and maximises the smallest of the three margins, each relative to its
// requirement:
//   min((a_red - a_green) / 80, red b* gap / 35, green b* gap / 35).
// Shade lightness follows the authors' prints: red-0 a little darker than
// red-1, green-1 darker than green-0, all within 4 L* units. Without a hue
// limit the search drifts to magenta (a* is largest there), so the reds keep
// a hue angle in [-25, 60] degrees (red-0 towards magenta, red-1 towards
// orange; the authors' reds are near 5 and 15) and the greens in [95, 185]
// (green-1 towards teal, green-0 towards yellow; the authors' near 140, 127).
//
// Usage: design_palette > families/palettes/default.json
#include <cmath>
#include <cstdio>

#include "chromatag/families/color.h"
#include "chromatag/families/palette.h"

namespace {

using chromatag::kPi;
using chromatag::Lab;

constexpr double kInset = 12.0 / 255.0;

bool HueWithin(const Lab& lab, double low_degrees, double high_degrees) {
  double hue = std::atan2(lab.b, lab.a) * 180.0 / kPi;
  if (hue < low_degrees) hue += 360.0;
  return hue >= low_degrees && hue <= high_degrees;
}

bool Printable(const Lab& lab) {
  if (lab.a > 0.0 ? !HueWithin(lab, -25.0, 60.0) : !HueWithin(lab, 95.0, 185.0)) return false;
  const chromatag::Rgb rgb = chromatag::LabToSrgb(lab);
  for (double v : {rgb.r, rgb.g, rgb.b}) {
    if (v < kInset || v > 1.0 - kInset) return false;
  }
  return true;
}

// The printable range of b* at (L, a), scanned in steps of 0.25.
bool BRange(double L, double a, double* lo, double* hi) {
  bool found = false;
  for (double b = -100.0; b <= 100.0; b += 0.25) {
    if (!Printable({L, a, b})) continue;
    if (!found) *lo = b;
    *hi = b;
    found = true;
  }
  return found;
}

}  // namespace

int main() {
  // Lightness offsets from the common L: red-1, red-0, green-1, green-0.
  const double kRed1 = 0.0, kRed0 = -2.0, kGreen1 = -2.0, kGreen0 = 2.0;
  double best = -1.0;
  chromatag::Palette palette;
  for (double L = 35.0; L <= 75.0; L += 1.0) {
    for (double a_red = 20.0; a_red <= 90.0; a_red += 1.0) {
      double red1_lo = 0, red1_hi = 0, red0_lo = 0, red0_hi = 0;
      if (!BRange(L + kRed1, a_red, &red1_lo, &red1_hi)) continue;
      if (!BRange(L + kRed0, a_red, &red0_lo, &red0_hi)) continue;
      const double red_gap = red1_hi - red0_lo;
      for (double a_green = -90.0; a_green <= -20.0; a_green += 1.0) {
        const double a_score = (a_red - a_green) / 80.0;
        if (std::fmin(a_score, red_gap / 35.0) <= best) continue;
        double green1_lo = 0, green1_hi = 0, green0_lo = 0, green0_hi = 0;
        if (!BRange(L + kGreen1, a_green, &green1_lo, &green1_hi)) continue;
        if (!BRange(L + kGreen0, a_green, &green0_lo, &green0_hi)) continue;
        const double green_gap = green0_hi - green1_lo;
        const double score = std::fmin(a_score, std::fmin(red_gap, green_gap) / 35.0);
        if (score <= best) continue;
        best = score;
        palette[chromatag::Shade::kRed1] = {L + kRed1, a_red, red1_hi};
        palette[chromatag::Shade::kRed0] = {L + kRed0, a_red, red0_lo};
        palette[chromatag::Shade::kGreen1] = {L + kGreen1, a_green, green1_lo};
        palette[chromatag::Shade::kGreen0] = {L + kGreen0, a_green, green0_hi};
      }
    }
  }
  // Black and white as printed by any printer: no ink, and full ink.
  palette[chromatag::Shade::kBlack] = {0.0, 0.0, 0.0};
  palette[chromatag::Shade::kWhite] = {100.0, 0.0, 0.0};
  palette.name = "default";
  char description[256];
  std::snprintf(description, sizeof(description),
                "ChromaTag toolkit default: spec section 6 margins maximised inside sRGB with "
                "8-bit channels in [12, 243] (score %.3f; see docs/palettes.md)",
                best);
  palette.description = description;
  std::fputs(chromatag::PaletteToJson(palette).c_str(), stdout);
  return 0;
}
