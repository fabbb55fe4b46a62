// Round trip: every tag a sheet's sidecar describes is found exactly once,
// with the right ID and no bit corrected, where the sidecar says; nothing
// else is found. `chromatag verify SHEET` is this, plus printing.
#ifndef CHROMATAG_VERIFY_SHEET_CHECK_H_
#define CHROMATAG_VERIFY_SHEET_CHECK_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/detector/detector.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"

namespace chromatag {

struct VerifyOptions {
  // Resolution PDF and SVG pages are rasterised at, pixels per inch. Higher
  // checks small tags better and takes longer. [50, 1200].
  double dpi = 200.0;
  // Largest accepted distance between a detected corner and the sidecar's,
  // mm. A tag moved by more than this on the page fails.
  double max_position_error_mm = 0.5;

  bool IsValid(std::string* error) const;
};

// The verdict on one tag of the sidecar.
struct TagVerdict {
  PlacedTag expected;
  int times_found = 0;
  int found_id = -1;  // ID of the (first) detection at its place; -1 if none.
  int hamming = 0;
  double margin = 0.0;
  double position_error_mm = 0.0;  // Worst corner, mm.
  bool passed = false;
  std::string problem;  // Empty when passed; otherwise names what is wrong.
};

// A detection where the sidecar has no tag.
struct UnexpectedDetection {
  int page = 0;
  std::string family;
  int id = -1;
  std::array<double, 2> center_mm{};
  // The sheet's own family, read with no bit corrected: not a false decode
  // of something else in view.
  bool exact = false;
};

struct SheetVerdict {
  std::vector<TagVerdict> tags;
  std::vector<UnexpectedDetection> unexpected;
  // The sheet file's bytes differ from the SHA-256 in its sidecar.
  std::vector<std::string> file_problems;
  bool passed = false;
  int tags_passed = 0;
};

// Checks the sheet's pages against the sidecar with `detector` (which should
// look for every family, so strays of another family are found too), one
// page rasterised at a time. Refuses (nullopt, *error) a page that cannot be
// rendered.
std::optional<SheetVerdict> CheckSheet(const SheetRecord& record, const SheetPages& pages,
                                       const Detector& detector, const VerifyOptions& options,
                                       std::string* error = nullptr);

// The sidecar beside a sheet file (.pdf, .svg, .png), which must describe
// that file. Refuses (nullopt, *error) a missing sheet, what ReadSidecar
// refuses, and a sidecar copied or renamed beside another sheet.
std::optional<SheetRecord> ReadSheetSidecar(const std::string& sheet_path,
                                            std::string* error = nullptr);

// The whole round trip for a sheet file (.pdf, .svg or .png) whose sidecar is
// beside it: read the sidecar, check the files' hashes, rasterise, detect and
// check. Refuses (nullopt, *error) bad options, a missing or broken sidecar or
// an unreadable sheet.
std::optional<SheetVerdict> VerifySheetFile(const std::string& sheet_path,
                                            const VerifyOptions& options,
                                            std::string* error = nullptr);

struct TagStress;  // stress.h

// `chromatag verify SHEET --json`'s document, on one line: the verdict
// (passed, tags_passed, tags, unexpected, file_problems; pages from 1),
// "sheet" as given, and "stress" (StressJson) when `stress` is not null.
// Text that is not UTF-8 is written with U+FFFD.
std::string SheetVerdictJson(const SheetVerdict& verdict, const std::string& sheet,
                             const std::vector<TagStress>* stress = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_SHEET_CHECK_H_
