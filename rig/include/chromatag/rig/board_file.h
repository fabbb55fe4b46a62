// Board files (docs/pose.md, "Board files"): what `detect --board` and the
// Python module's Board.from_file read.
//
// - A generated sheet's sidecar ("chromatag-layout"): every tag of its one
//   page on one plane. A board written with `generate --board` has its
//   origin at the bottom-left corner of the bottom-left tag's black square;
//   any other sheet at the page's bottom-left corner. x right, y up the
//   page, z out of it; metres.
// - A colour calibration sheet's sidecar ("chromatag-calib-sheet"): its
//   corner tags, origin at the page's bottom-left corner, axes as above.
// - A bundle YAML in the shape apriltag_ros uses for tag_bundles: per tag
//   id, size (the black square, metres), x, y, z (0 when left out) and the
//   unit quaternion qw, qx, qy, qz of the tag in the bundle frame (identity
//   when left out); plus `family` (per tag or for the bundle) and an
//   optional `palette`.
#ifndef CHROMATAG_RIG_BOARD_FILE_H_
#define CHROMATAG_RIG_BOARD_FILE_H_

#include <optional>
#include <string>

#include "chromatag/detector/board.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "chromatag/layout/sheet_record.h"

namespace chromatag {

// The board a sheet's sidecar describes. Refuses a sheet of more than one
// page (its pages need not lie on one plane).
std::optional<Board> BoardFromSheet(const SheetRecord& sheet, std::string* error = nullptr);

// The board of a colour calibration sheet: its corner tags.
std::optional<Board> BoardFromCalibSheet(const CalibSheetLayout& layout,
                                         std::string* error = nullptr);

// The bundle called `name` in a bundle YAML's tag_bundles (empty: the file's
// only bundle). Refuses (nullopt, *error) anything else, saying what.
std::optional<Board> ParseBundleYaml(const std::string& text, const std::string& name,
                                     std::string* error = nullptr);

// Reads `spec`: a sheet file (.pdf, .svg, .png) with its sidecar beside it
// (ReadSidecarOfSheet), a sidecar (.json) or a bundle YAML (.yaml, .yml),
// with "#NAME" after the path to choose a bundle of several. *error names
// the file and what is wrong with it.
std::optional<Board> ReadBoardFile(const std::string& spec, std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_RIG_BOARD_FILE_H_
