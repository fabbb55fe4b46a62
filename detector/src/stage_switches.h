// Switches for the detector's own additions to the paper's Algorithm 1, so
// that a benchmark can measure what each one buys (bench/pair_timing --off).
// Not in DetectorOptions: they are always on for users. The Detector keeps
// them; the stages that test refine_corners (PolyToQuad, NestedAndRefined,
// DecodeCandidate) take them whole, and Decode's colour split and
// likelihood-ratio reads find theirs in each family's FamilyDecoder.
#ifndef CHROMATAG_DETECTOR_SRC_STAGE_SWITCHES_H_
#define CHROMATAG_DETECTOR_SRC_STAGE_SWITCHES_H_

#include <memory>
#include <string>

#include "chromatag/detector/detector.h"

namespace chromatag::internal {

struct StageSwitches {
  // Sub-pixel sides (refine_corners.cc): least-squares lines through edge
  // points along each side, intersected. Off gives the corners of the
  // clustered polygon, about a pixel off, and turns quads_from_scans off
  // too (its quads only start the sub-pixel sides).
  bool refine_corners = true;

  // The fast path from InitialScan to the sub-pixel sides
  // (quad_from_scans.cc). Off sends every candidate through BuildPolygon's
  // greedy scans, as the paper does.
  bool quads_from_scans = true;

  // The second path (grow_region.cc, Stage::kGrowRegion) for candidates
  // whose red is enclosed by green but which the ring scans or a later stage
  // lose.
  bool grow_regions = true;

  // Decode's second soft read (ColourSplitRead in decode.cc), which scores
  // each colour's split of the cells against that colour's own gap.
  bool colour_split_read = true;

  // Decode's last read (MisfitRatioRead in decode.cc): the likelihood-ratio
  // test between the codes and swapped prints (every one for close codes,
  // those near the observed bits for far ones), for reads the other rules
  // refuse.
  bool misfit_ratio_read = true;
};

// Detector::Create with some of the detector's additions turned off.
std::unique_ptr<Detector> CreateDetector(const DetectorOptions& options,
                                         const StageSwitches& switches,
                                         std::string* error = nullptr);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_STAGE_SWITCHES_H_
