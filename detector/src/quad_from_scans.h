// The fast path from InitialScan to the sub-pixel sides
// (quad_from_scans.cc): the four diagonal scans through the rings added to
// InitialScan's four axis ones, and each ring's quad from its eight border
// points, split into four runs of consecutive points, one per side, whose
// edge directions run across their sides. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_QUAD_FROM_SCANS_H_
#define CHROMATAG_DETECTOR_SRC_QUAD_FROM_SCANS_H_

#include "candidate.h"
#include "chromatag/detector/options.h"
#include "image_view.h"
#include "scan_rings.h"

namespace chromatag::internal {

// QuadsFromScans: false when no split gives a quad for every ring; the
// candidate's points and scan directions are left as they were (only its
// quads are written), so that BuildPolygon can take over.
bool QuadsFromScans(const ImageView& image, const DetectorOptions& options,
                    RingScanBuffers* buffers, Candidate* candidate);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_QUAD_FROM_SCANS_H_
