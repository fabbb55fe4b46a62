// Palettes: the six colours a ChromaTag is printed in, as CIELAB data.
//
// Spec sections 3 and 6. A palette is chosen at generation time, recorded in
// the sidecar and the PDF metadata, and can be replaced by the calibration
// tool. Its file format is JSON:
//
//   {
//     "format": "chromatag-palette", "version": 1,
//     "name": "my-printer",
//     "description": "free text",
//     "lab": {"red-1": [L, a, b], "red-0": [...], "green-1": [...],
//             "green-0": [...], "black": [...], "white": [...]}
//   }
//
// "format", "version", "name" and "description" are optional.
#ifndef CHROMATAG_FAMILIES_PALETTE_H_
#define CHROMATAG_FAMILIES_PALETTE_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/families/color.h"

namespace chromatag {

// The six shades. Bit 1 of a red cell is red-1 (the more orange red, higher
// b*), bit 0 red-0 (more magenta, lower b*); bit 1 of a green cell is green-1
// (darker, bluer, lower b*), bit 0 green-0 (lighter yellow-green, higher b*).
enum class Shade { kRed1 = 0, kRed0, kGreen1, kGreen0, kBlack, kWhite };
inline constexpr int kNumShades = 6;
inline constexpr std::array<Shade, kNumShades> kAllShades = {
    Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0, Shade::kBlack, Shade::kWhite};

const char* ShadeName(Shade shade);  // "red-1", ...
std::optional<Shade> ShadeFromName(const std::string& name);

struct Palette {
  std::string name;
  std::string description;
  std::array<Lab, kNumShades> lab;

  const Lab& operator[](Shade shade) const { return lab[static_cast<int>(shade)]; }
  Lab& operator[](Shade shade) { return lab[static_cast<int>(shade)]; }
  // The 8-bit sRGB value written into files (clipped if out of gamut).
  Rgb8 Srgb8(Shade shade) const { return LabToSrgb8((*this)[shade]); }
};

// One constraint and whether the palette meets it.
struct PaletteCheck {
  enum class Level {
    // Needed for the detector to find and decode the tag; a palette file that
    // breaks one is refused.
    kRequired,
    // The design rules of spec section 6 for good margins in print; the
    // `default` palette meets all of them, others are warned about.
    kRecommended,
  };
  std::string id;           // Stable short name, e.g. "red-a-equal".
  std::string description;  // What is asked, e.g. "a*(red-1) = a*(red-0) within 2".
  Level level = Level::kRequired;
  bool passed = false;
  std::string detail;  // What was measured, e.g. "|46.0 - 44.1| = 1.9".
};

// Thresholds used by CheckPalette; the recommended values are spec section 6,
// the required ones the smallest differences the detector's default
// thresholds can use (ADiffThresh = 25 in a*).
struct PaletteLimits {
  double min_red_green_a_gap_required = 25.0;
  double min_shade_b_gap_required = 6.0;
  double min_border_l_gap_required = 20.0;  // Black and white vs. every chromatic L*.
  double gamut_tolerance = 2e-3;            // In linear RGB.

  double max_a_spread_recommended = 2.0;
  double min_red_green_a_gap_recommended = 80.0;
  double min_shade_b_gap_recommended = 35.0;
  double max_chromatic_l_spread_recommended = 5.0;
  double max_black_l_recommended = 10.0;
  double min_white_l_recommended = 95.0;
};

std::vector<PaletteCheck> CheckPalette(const Palette& palette, const PaletteLimits& limits = {});

// True if every required check passed; otherwise *error (if given) lists the
// failed ones, separated by "; ".
bool MeetsRequiredChecks(const std::vector<PaletteCheck>& checks, std::string* error = nullptr);

// Names of the built-in palettes: "default", "iccv17".
std::vector<std::string> BuiltinPaletteNames();

// A built-in palette by name, or nullopt with *error naming the valid ones.
std::optional<Palette> BuiltinPalette(const std::string& name, std::string* error = nullptr);

// Parses palette JSON and refuses (nullopt, *error) malformed text, missing or
// unknown shades, non-numeric or out-of-range values, and palettes that break a
// required check. `default_name` is used when the file has no "name".
std::optional<Palette> ParsePalette(const std::string& json_text, const std::string& default_name,
                                    std::string* error = nullptr);

// Reads and parses a palette file (see ParsePalette); a missing or unreadable
// file is an error naming the path.
std::optional<Palette> LoadPaletteFile(const std::string& path, std::string* error = nullptr);

// Serialises a palette in the file format above (CIELAB only).
std::string PaletteToJson(const Palette& palette);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_PALETTE_H_
