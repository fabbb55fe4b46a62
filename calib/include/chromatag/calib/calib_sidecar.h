// The calibration sheet's sidecar JSON: every patch's position and intended
// colour, the corner tags and the sheet ID (docs/calibration.md, "Sidecar").
// Same conventions as the generator's sidecar: millimetres from the page's
// top-left corner, x right, y down, a named schema with a version.
#ifndef CHROMATAG_CALIB_CALIB_SIDECAR_H_
#define CHROMATAG_CALIB_CALIB_SIDECAR_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/calib/calib_sheet.h"
#include "chromatag/generator/file_util.h"

namespace chromatag {

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

// The text of the sidecar beside a sheet file (`sheet_path` + ".json", into
// *sidecar_path), once it is known to describe that file: its "files" list
// names the sheet and records the sheet's SHA-256. Any sheet the toolkit
// writes (generate, calib-sheet) has one. `kind` names the sheet in errors.
std::optional<std::string> ReadSidecarOfSheet(const std::string& sheet_path,
                                              const std::string& kind, std::string* sidecar_path,
                                              std::string* error);

// A calibration sheet given as the user has it: its sidecar (.json), or the
// sheet itself (.pdf, .png) with its sidecar beside it, as `verify` takes a
// sheet. For a sheet file the sidecar must list it, and the file must be
// unchanged since it was written (the SHA-256 the sidecar records): the
// patches' intended colours come from the sidecar.
std::optional<CalibSheetLayout> ReadCalibSheet(const std::string& path,
                                               std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CALIB_SIDECAR_H_
