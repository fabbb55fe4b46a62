// 5. Decode: picks the family whose ring proportions match, reads every
// payload cell in b*, splits each colour at its own midpoint, looks the code
// up over all rotations and fills the detection in the decoded orientation.
// Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_DECODE_H_
#define CHROMATAG_DETECTOR_SRC_DECODE_H_

#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "chromatag/families/decoder.h"
#include "chromatag/families/family.h"
#include "image_view.h"
#include "kernels/kernels.h"
#include "refine_corners.h"
#include "stage_switches.h"

namespace chromatag::internal {

// A family the detector looks for, with its decoder.
struct FamilyDecoder {
  std::shared_ptr<const TagFamily> family;
  std::unique_ptr<CodeDecoder> decoder;
  // What a tag printed with its shades swapped shows: within each colour,
  // the complement of each kept code in each of its four orientations
  // (SwappedCodes; Decode compares close-code reads with them).
  std::vector<Code> swapped_codes;
  // Each kept ID's code in its four orientations: kept_ids()[i] turned r
  // quarter turns at 4 i + r (OrientedCodes; the soft reads try them all).
  std::vector<Code> oriented_codes;
  // Whether a read the blur model refuses gets the colour-by-colour soft
  // read (StageSwitches::colour_split_read; always on for users).
  bool colour_split_read = true;
  // Whether a read every other rule refuses gets the likelihood-ratio read
  // (StageSwitches::misfit_ratio_read; always on for users).
  bool misfit_ratio_read = true;
};

// The swapped prints' codes of `family` (FamilyDecoder::swapped_codes).
std::vector<Code> SwappedCodes(const TagFamily& family);
// FamilyDecoder::oriented_codes of `family`.
std::vector<Code> OrientedCodes(const TagFamily& family);

// Decode reads each cell as the mean colour of a samples x samples grid of
// pixels: the ones nearest to centre + s du + t dv, s and t evenly from -1 to
// 1 (samples from 2 to 8). SumCellGrid sums their R, G and B and counts them,
// points outside the frame skipped; eight points at a time by the view's
// vector kernel where it has one, with the same sums (PixelSums:
// kernels/kernels.h).
PixelSums SumCellGrid(const ImageView& image, cv::Point2d centre, cv::Point2d du, cv::Point2d dv,
                      int samples);

// Reads `candidate` as each family its rings fit, best first. *why: the
// best-fitting family's reason. With `fits_swapped_print`, sets it (never
// clears it) when any family's read was refused as a swapped print, whatever
// reason *why gives.
bool Decode(const ImageView& image, const DetectorOptions& options,
            const std::vector<FamilyDecoder>& families, const Candidate& candidate,
            SideFitBuffers* buffers, Detection* detection, RejectReason* why,
            bool* fits_swapped_print = nullptr);

// Decode for a candidate whose inner quads are still rough (from the scans or
// the polygons; only the outer one has its sub-pixel sides): where they fit
// no family's proportions, RefineInnerQuads (unless the benchmarks turned
// StageSwitches::refine_corners off) and Decode once more. The first reason
// stands if that fails too. A read of either pass refused as a swapped print
// sets Candidate::fits_swapped_print.
bool DecodeCandidate(const ImageView& image, const DetectorOptions& options,
                     const StageSwitches& switches, const std::vector<FamilyDecoder>& families,
                     SideFitBuffers* buffers, Candidate* candidate, Detection* detection,
                     RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_DECODE_H_
