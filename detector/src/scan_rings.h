// ScanRings (scan_rings.cc), the ring scan InitialScan, QuadsFromScans and
// BuildPolygon make: one scan outwards from `start` along the unit vector
// `direction`, one pixel (nearest) per unit step, through the three borders.
// ReferenceRed is carried in; ReferenceGreen and ReferenceBlack are picked up
// on the way. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_SCAN_RINGS_H_
#define CHROMATAG_DETECTOR_SRC_SCAN_RINGS_H_

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "chromatag/detector/options.h"
#include "image_view.h"

namespace chromatag::internal {

// ScanRings' buffers: the values read along a scan, one per step.
struct RingScanBuffers {
  std::vector<float> values;
};

// The a* drop from ReferenceRed that counts a pixel as past the red/green
// border: BorderThresh, or a third of the red's a* if more. The two reds share
// one a* in the palettes, but a colour cast or JPEG's chroma blur part them by
// 10 units or more, and BorderThresh alone then stops scans inside the red.
// Green's a* is negative, so the drop across the border always exceeds the
// red's a*.
inline float RedGreenThresh(const DetectorOptions& options, float reference_red) {
  return std::max(static_cast<float>(options.border_thresh), reference_red / 3.f);
}

// False if a border is not found within reach of the previous one or the scan
// leaves the frame; the red/green border must lie within `red_reach` steps
// of `start` (by default anywhere in the frame).
bool ScanRings(const ImageView& image, const DetectorOptions& options, cv::Point2f start,
               cv::Point2f direction, float reference_red, RingScanBuffers* buffers, RingHits* hits,
               int red_reach = -1);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_SCAN_RINGS_H_
