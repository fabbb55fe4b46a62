// Scratch memory. A stage that needs buffers takes them from its caller, one
// struct per kind of work (declared with the stage), so that its signature
// says what it writes besides its results; the detector keeps one of each in
// its Scratch, reused from call to call, so that a warm Detect allocates
// nothing. The buffers carry nothing from one call to the next that a call
// reads. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_SCRATCH_H_
#define CHROMATAG_DETECTOR_SRC_SCRATCH_H_

#include <vector>

#include "build_polygon.h"
#include "candidate.h"
#include "find_adiff.h"
#include "grow_region.h"
#include "initial_scan.h"
#include "poly_to_quad.h"
#include "refine_corners.h"
#include "scan_rings.h"

namespace chromatag::internal {

// What one Detect works in: the candidate the stages build up, the frame's
// accepted areas and rejected regions, and the stages' buffers. The detector
// keeps a pool of them, one per Detect in flight, so that several threads can
// share it; a test that calls the stages directly makes its own.
struct Scratch {
  Candidate candidate;
  std::vector<DetectedArea> areas;
  RowScanBuffers row_scan;  // FindADiff.
  std::vector<RejectedRegion> rejected;
  RingScanBuffers ring_scan;  // InitialScan, QuadsFromScans, BuildPolygon.
  PolygonBuffers polygon;     // BuildPolygon.
  QuadFitBuffers quad_fit;    // PolyToQuad, GrowRegion.
  SideFitBuffers side_fit;    // NestedAndRefined, PolyToQuad, DecodeCandidate, GrowRegion.
  RegionBuffers region;       // GrowRegion.
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_SCRATCH_H_
