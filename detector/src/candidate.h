// The stages of Algorithm 1 (paper section 4), one file and one function
// each, and the candidate they build up: what all stages share. Each stage is
// declared in its own header, next to its file. Stages 2-5 return false and
// set *why when they abandon a candidate. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_CANDIDATE_H_
#define CHROMATAG_DETECTOR_SRC_CANDIDATE_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry.h"
#include "tag_light.h"

namespace chromatag::internal {

// The three borders a scan from the tag centre crosses, inside out.
enum Ring { kRedGreen = 0, kGreenBlack = 1, kBlackWhite = 2 };
inline constexpr int kNumRings = 3;

// Where one scan from the centre crossed each border (sub-pixel), and the
// pixels that show the green ring's and the quiet zone's colours (the ring's
// middle, half a black ring's width into the quiet zone).
struct RingHits {
  std::array<cv::Point2f, kNumRings> border;
  cv::Point green_at;
  cv::Point white_at;
};

// A tag candidate as the stages build it.
struct Candidate {
  cv::Point2f centre;       // Converged centre of the red region (InitialScan).
  float reference_red = 0;  // ReferenceRed, a*.
  // Border points per ring, from every scan (InitialScan and BuildPolygon).
  std::array<std::vector<cv::Point2f>, kNumRings> points;
  std::vector<cv::Point2f> scan_directions;  // Unit directions already scanned.
  std::array<Quad, kNumRings> quads;
  // The red/green border points of InitialScan's last completed centring
  // pass, in eight directions from `centre`: a red region enclosed by
  // far less red. `enclosed` is false until a pass completed.
  bool enclosed = false;
  std::array<cv::Point2f, 8> red_border;
  // The quiet zone's white from InitialScan's final scans, settled.
  TagLight light;
  // Its seed lay in a rejected region and spent one of its retries
  // (RejectedRegion::retries): when it fails it adds no region of its own.
  bool retry = false;
  // Its red's index among the frame's rejected regions: the region it spent
  // a retry of, or the one InitialScan added when it rejected it; -1 if
  // neither. Valid while this seed's stages run (the regions are forgotten
  // row by row, between seeds).
  int region = -1;
  // Some read of it, by Decode or GrowRegion in any family, was refused as
  // fitting a swapped print (its region then keeps no retries).
  bool fits_swapped_print = false;
};

// The eight directions InitialScan and QuadsFromScans scan in from a
// candidate's centre, clockwise on screen from "right": the axes (right,
// down, left, up; the paper's four scans) at even indices, the diagonals
// between them. Unit steps, so that every scan samples a ring as densely (M
// pixels must fit in a ring whatever the direction).
inline constexpr float kDiagonalStep = 0.70710678f;
inline const cv::Point2f kScanDirections[8] = {
    {1, 0},  {kDiagonalStep, kDiagonalStep},   {0, 1},  {-kDiagonalStep, kDiagonalStep},
    {-1, 0}, {-kDiagonalStep, -kDiagonalStep}, {0, -1}, {kDiagonalStep, -kDiagonalStep}};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_CANDIDATE_H_
