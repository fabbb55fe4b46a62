// Why ChromaTag missed a tag: the paper's Table 4(b), exactly. The detector
// reports its rejected candidates when asked (DetectorOptions::
// report_rejected); a miss is put down to the deepest stage, then the latest
// reason in the detector's list, among the candidates that started on the
// tag, or to FindADiff ("no candidate") when none did. A candidate the second
// path also tried counts as abandoned in GrowRegion, for GrowRegion's reason,
// with the scans' reason in brackets.
#ifndef CHROMATAG_BENCH_MISS_ANALYSIS_H_
#define CHROMATAG_BENCH_MISS_ANALYSIS_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/bench/dataset.h"
#include "chromatag/detector/detection.h"

namespace chromatag::bench {

// The reasons that are not the detector's own RejectReason.
inline constexpr const char* kNoCandidate = "no candidate";
// The detector reported something on the tag, but not the tag.
inline constexpr const char* kReportedWrongId = "reported with a wrong family or ID";
inline constexpr const char* kReportedMisplaced = "reported with corners off (IoU < 0.5)";
// Found when run again (should not happen: the detector is deterministic).
inline constexpr const char* kFoundOnRerun = "found when run again";

struct MissCause {
  bool analysed = false;  // False for frames not analysed (found, or no tag).
  // A Stage as an int (the enum may grow: loop over kNumStages), or
  // kNumStages for "reported" (the tag was reported, but wrongly).
  int stage = 0;
  std::string reason;  // RejectReasonName, kNoCandidate or a kReported* text.
  int candidates = 0;  // Rejected candidates that started on the tag.
};

// "FindADiff", ..., or "reported" for stage kNumStages.
std::string MissStageName(int stage);

// The tag's outer border in the image: the black square grown by its quiet
// zone (`quiet_cells` of a square `square_cells` wide), same corner order.
std::array<cv::Point2d, 4> OuterBorder(const TagTruth& truth, int square_cells, int quiet_cells);

// Assigns a miss of `truth` from the detector's full output on the frame,
// with rejected candidates reported. A candidate is on the tag when its
// seed or its centre lies within the tag's outer border.
MissCause AssignMiss(const DetectionResult& result, const TagTruth& truth, int square_cells,
                     int quiet_cells);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_MISS_ANALYSIS_H_
