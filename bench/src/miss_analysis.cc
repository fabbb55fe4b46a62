#include "chromatag/bench/miss_analysis.h"

#include <opencv2/imgproc.hpp>

#include "chromatag/bench/metrics.h"

namespace chromatag::bench {
namespace {

bool Inside(const std::array<cv::Point2d, 4>& quad, const cv::Point2d& point) {
  const std::vector<cv::Point2f> polygon(quad.begin(), quad.end());
  return cv::pointPolygonTest(polygon, cv::Point2f(point), false) >= 0;
}

cv::Point2d Centre(const std::array<cv::Point2d, 4>& quad) {
  return (quad[0] + quad[1] + quad[2] + quad[3]) / 4.0;
}

}  // namespace

std::string MissStageName(int stage) {
  if (stage >= 0 && stage < kNumStages) return StageName(static_cast<Stage>(stage));
  return "reported";
}

std::array<cv::Point2d, 4> OuterBorder(const TagTruth& truth, int square_cells, int quiet_cells) {
  const cv::Point2f unit[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  cv::Point2f image[4];
  for (int i = 0; i < 4; ++i) image[i] = truth.corners[i];
  const cv::Matx33d image_from_square(cv::getPerspectiveTransform(unit, image));
  const double grow = static_cast<double>(quiet_cells) / square_cells;
  std::array<cv::Point2d, 4> outer;
  for (int i = 0; i < 4; ++i) {
    const double u = unit[i].x == 0 ? -grow : 1 + grow, v = unit[i].y == 0 ? -grow : 1 + grow;
    const cv::Vec3d p = image_from_square * cv::Vec3d(u, v, 1);
    outer[i] = {p[0] / p[2], p[1] / p[2]};
  }
  return outer;
}

MissCause AssignMiss(const DetectionResult& result, const TagTruth& truth, int square_cells,
                     int quiet_cells) {
  MissCause cause;
  cause.analysed = true;
  const auto outer = OuterBorder(truth, square_cells, quiet_cells);
  // Something reported on the tag that is not the tag.
  for (const Detection& d : result.detections) {
    if (QuadIoU(d.corners, truth.corners) >= 0.5) {
      const bool right = d.id == truth.id && d.family && d.family->name() == truth.family;
      cause.stage = kNumStages;
      cause.reason = right ? kFoundOnRerun : kReportedWrongId;
      return cause;
    }
    if (Inside(outer, Centre(d.corners))) {
      cause.stage = kNumStages;
      cause.reason = kReportedMisplaced;
    }
  }
  if (cause.stage == kNumStages) return cause;
  int deepest_stage = -1, deepest_reason = -1;
  for (const RejectedCandidate& r : result.rejected) {
    if (!Inside(outer, cv::Point2d(r.seed)) && !Inside(outer, cv::Point2d(r.centre))) continue;
    ++cause.candidates;
    // A candidate the second path tried too was abandoned there last.
    const int stage = static_cast<int>(r.grown ? Stage::kGrowRegion : r.stage);
    const int reason = static_cast<int>(r.grown ? r.grow_reason : r.reason);
    if (stage > deepest_stage || (stage == deepest_stage && reason > deepest_reason)) {
      deepest_stage = stage;
      deepest_reason = reason;
      cause.reason = r.grown ? std::string(RejectReasonName(r.grow_reason)) +
                                   " (scans: " + RejectReasonName(r.reason) + ")"
                             : RejectReasonName(r.reason);
    }
  }
  if (deepest_stage < 0) {
    cause.stage = static_cast<int>(Stage::kFindADiff);
    cause.reason = kNoCandidate;
  } else {
    cause.stage = deepest_stage;
  }
  return cause;
}

}  // namespace chromatag::bench
