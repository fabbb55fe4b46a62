// 3. BuildPolygon: greedy scans towards the largest convexity-limited
// potential area of the outer polygon until area / (area + potential) exceeds
// ConvThresh. Every scan adds a point to each of the three polygons. Internal
// to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_BUILD_POLYGON_H_
#define CHROMATAG_DETECTOR_SRC_BUILD_POLYGON_H_

#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "image_view.h"
#include "scan_rings.h"

namespace chromatag::internal {

// BuildPolygon's buffers: the outer polygon's hull, and the points sorted for
// it (ClockwiseHull).
struct PolygonBuffers {
  std::vector<cv::Point2f> sorted, hull;
};

bool BuildPolygon(const ImageView& image, const DetectorOptions& options,
                  RingScanBuffers* scan_buffers, PolygonBuffers* buffers, Candidate* candidate,
                  RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_BUILD_POLYGON_H_
