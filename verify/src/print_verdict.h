// The print check's verdicts (print_check.h): what the measured page and
// tags say about the print, each finding graded pass, warn or fail and put
// in words, worst first.
#ifndef CHROMATAG_VERIFY_SRC_PRINT_VERDICT_H_
#define CHROMATAG_VERIFY_SRC_PRINT_VERDICT_H_

#include <string>
#include <vector>

#include "chromatag/detector/detection.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/print_check.h"

namespace chromatag::internal {

struct Finding {
  Grade grade;
  std::string text;
};

void AddFinding(std::vector<Finding>* findings, Grade grade, std::string text);

// The findings worst first (in the order found within a grade) into
// *problems and *grades; *grade the worst of them, kPass for none.
void Settle(std::vector<Finding> findings, Grade* grade, std::vector<std::string>* problems,
            std::vector<Grade>* grades);

// The page as a whole: a scan's scale and skew, a photo's aspect (sets
// r->geometry_checked), the fit's residual, and tags found where the
// sidecar has none (r->unexpected).
void JudgePage(const PrintCheckOptions& o, const SheetRecord& record, PrintPageResult* r,
               std::vector<Finding>* findings);

// A scan whose scale is far off 1 with the resolution read from its file:
// most likely the scanner used another one.
void JudgeScanDpi(const PrintImage& image, const PrintPageResult& r,
                  std::vector<Finding>* findings);

// One tag, into t->grade and its problems: its printed size (scans; within
// the scale tolerance plus `size_allowance`, relative), its shades against
// what the detector needs, whether and how it decoded, and its position.
void JudgeTag(const PrintCheckOptions& o, const SheetRecord& record, bool scan,
              double size_allowance, PrintTagResult* t);

// Why no page was recognised: no tag of the sheet decoded; with the
// undecoded candidates' mean splits (r.undecoded) against the palette's,
// which shades print alike.
std::string NoPageProblem(const SheetRecord& record, const DetectionResult& result,
                          const PrintCheckOptions& options, const PrintPageResult& r);

}  // namespace chromatag::internal

#endif  // CHROMATAG_VERIFY_SRC_PRINT_VERDICT_H_
