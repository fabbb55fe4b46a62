// 4. PolyToQuad: a quad per polygon (FitQuad: the hull cut to four corners,
// a line per side, their intersections); then NestedAndRefined. Internal to
// the detector.
#ifndef CHROMATAG_DETECTOR_SRC_POLY_TO_QUAD_H_
#define CHROMATAG_DETECTOR_SRC_POLY_TO_QUAD_H_

#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "chromatag/detector/detection.h"
#include "geometry.h"
#include "image_view.h"
#include "refine_corners.h"
#include "stage_switches.h"

namespace chromatag::internal {

// FitQuad's buffers: the points' hull (and the points sorted for it), the
// vertices still kept as the hull is cut to four corners, and each hull
// edge's side.
struct QuadFitBuffers {
  std::vector<cv::Point2f> sorted, hull;
  std::vector<int> prev, next;
  std::vector<double> area;
  std::vector<int> label;
};

// Four sides from the convex hull of `points` (the hull cut to its four
// corners by dropping the vertex of the smallest triangle, a line fitted
// through each side's hull edges) and their corners, clockwise. False if
// they do not make a convex quad.
bool FitQuad(const std::vector<cv::Point2f>& points, QuadFitBuffers* buffers, Quad* quad);

bool PolyToQuad(const ImageView& image, const StageSwitches& switches, QuadFitBuffers* fit_buffers,
                SideFitBuffers* side_buffers, Candidate* candidate, RejectReason* why);

// PolyToQuad's second half: false (and *why) unless the three quads are
// nested, each inside the next; then RefineOuterQuad (unless the benchmarks
// turned StageSwitches::refine_corners off).
bool NestedAndRefined(const ImageView& image, const StageSwitches& switches,
                      SideFitBuffers* buffers, Candidate* candidate, RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_POLY_TO_QUAD_H_
