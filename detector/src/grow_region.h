// The second path (grow_region.cc). WorthGrowing: whether a candidate the
// first path's stages lost (for `why`) is one the second path can rescue: its red
// was enclosed by green and it got as far as the ring scans. GrowRegion:
// grows the black square from the centre (everything darker than the quiet
// zone, levels from the candidate's own profiles), fits its four sides and
// refines them, places each family's green and red rings inside it and fits
// them on their edges, then Decode. Overwrites the candidate's quads and
// outer points. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_GROW_REGION_H_
#define CHROMATAG_DETECTOR_SRC_GROW_REGION_H_

#include <array>
#include <cstdint>
#include <vector>

#include "candidate.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "decode.h"
#include "image_view.h"
#include "poly_to_quad.h"
#include "refine_corners.h"

namespace chromatag::internal {

// GrowRegion's fill: each grid cell's state, the cells queued, and the
// outline's ends on each grid row.
struct RegionBuffers {
  std::vector<uint8_t> state;
  std::vector<int> queue;
  std::vector<std::array<float, 2>> row_ends;
};

bool WorthGrowing(const Candidate& candidate, RejectReason why);
bool GrowRegion(const ImageView& image, const DetectorOptions& options,
                const std::vector<FamilyDecoder>& families, RegionBuffers* region_buffers,
                QuadFitBuffers* fit_buffers, SideFitBuffers* side_buffers, Candidate* candidate,
                Detection* detection, RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_GROW_REGION_H_
