// The colour calibration sheet's layout, as its sidecar JSON records it
// (docs/calibration.md, "Sidecar"): every patch's position and intended
// colour, the corner tags and the sheet ID. Same conventions as the tag
// sheets' sidecar (sheet_record.h): millimetres from the page's top-left
// corner, x right, y down, a named schema with a version. The calibration
// library lays the sheet out and draws it; this is what is written and read.
#ifndef CHROMATAG_LAYOUT_CALIB_SHEET_LAYOUT_H_
#define CHROMATAG_LAYOUT_CALIB_SHEET_LAYOUT_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/families/color.h"
#include "chromatag/families/palette.h"

namespace chromatag {

enum class PatchKind {
  kPaper,      // Bare paper: the white reference.
  kPalette,    // One of the palette's shades (not white: white is the paper).
  kGrey,       // A level of the grey ramp.
  kCandidate,  // A candidate red or green.
};
const char* PatchKindName(PatchKind kind);  // "paper", "palette", "grey", "candidate".

struct Patch {
  int index = 0;  // Position in CalibSheetLayout::patches.
  PatchKind kind = PatchKind::kPaper;
  // kPalette: the shade. kCandidate: kRed1 for a red candidate, kGreen1 for
  // a green one (which shade it may become is decided by calibration).
  Shade shade = Shade::kWhite;
  Lab lab;   // Intended colour (the palette's or the candidate's CIELAB).
  Rgb8 rgb;  // What is sent to the printer: `lab` as 8-bit sRGB.
  // Square's top-left corner and side, mm.
  std::array<double, 2> origin_mm{0.0, 0.0};
  double size_mm = 0.0;
  int row = 0;  // Grid slot.
  int col = 0;

  std::array<double, 2> CenterMm() const {
    return {origin_mm[0] + size_mm / 2.0, origin_mm[1] + size_mm / 2.0};
  }
};

struct CornerTag {
  int id = 0;
  // Black square's corners: top-left of the upright tag first, clockwise
  // (spec section 7). Tags are printed upright.
  std::array<std::array<double, 2>, 4> corners_mm;
};

// Which page corner a corner tag sits in, in CalibSheetLayout::tags order.
inline constexpr std::array<const char*, 4> kCornerNames = {"top-left", "top-right", "bottom-right",
                                                            "bottom-left"};

struct CalibSheetLayout {
  int sheet_id = 0;
  Palette palette;
  PageSize page;
  std::string family = "16h5";  // Of the corner tags.
  double tag_size_mm = 0.0;
  int rows = 0;  // Patch grid.
  int columns = 0;
  std::array<CornerTag, 4> tags;  // Top-left, top-right, bottom-right, bottom-left.
  std::vector<Patch> patches;
};

inline constexpr const char* kCalibSheetSchema = "chromatag-calib-sheet";
inline constexpr int kCalibSheetSchemaVersion = 1;

// The sidecar text for `layout`, naming the page files it was written with
// (their base names and SHA-256).
std::string CalibSidecarJson(const CalibSheetLayout& layout,
                             const std::vector<OutputFile>& page_files);

// Parses and checks a sidecar: schema and version, a known family with kept
// corner-tag IDs, a valid palette, patches inside the page with valid
// colours. Refuses (nullopt, *error) anything else, saying what is wrong.
std::optional<CalibSheetLayout> ParseCalibSidecar(const std::string& text,
                                                  std::string* error = nullptr);

// Reads `path` and parses it; errors name the path.
std::optional<CalibSheetLayout> ReadCalibSidecar(const std::string& path,
                                                 std::string* error = nullptr);

// A calibration sheet given as the user has it: its sidecar (.json), or the
// sheet itself (.pdf, .png) with its sidecar beside it, as `verify` takes a
// sheet. For a sheet file the sidecar must list it, and the file must be
// unchanged since it was written (the SHA-256 the sidecar records): the
// patches' intended colours come from the sidecar.
std::optional<CalibSheetLayout> ReadCalibSheet(const std::string& path,
                                               std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_LAYOUT_CALIB_SHEET_LAYOUT_H_
