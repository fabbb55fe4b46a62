// Stage 2, InitialScan (paper section 4, Figure 6a-c).
#include <cmath>

#include "stages.h"

namespace chromatag::internal {
namespace {

constexpr int kMaxCentreIterations = 8;
constexpr float kConvergedPx = 0.75f;
// Smallest a* accepted as a tag's red: the palettes' reds have 40 or more, and
// a colour cast or a washed-out print lowers it.
constexpr float kMinRedA = 12.f;

// Right, down, left, up (the paper's four scans), then the diagonals; in
// clockwise order on screen.
// Unit steps, so that every scan samples a ring as densely (M pixels must fit
// in a ring whatever the direction).
constexpr float kD = 0.70710678f;
const cv::Point2f kDirections[8] = {{1, 0},  {kD, kD},   {0, 1},  {-kD, kD},
                                    {-1, 0}, {-kD, -kD}, {0, -1}, {kD, -kD}};

}  // namespace

bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed,
                 Candidate* candidate) {
  cv::Point2f centre(static_cast<float>(seed.x), static_cast<float>(seed.y));
  // The seed may sit on the blurred edge of the red; the reddest of it and
  // its neighbourhood is the better ReferenceRed.
  float reference_red = std::max(image.A(seed.x, seed.y), image.MeanA3x3(seed.x, seed.y));
  // A tag's red half-width is under half the frame unless the tag is larger
  // than the frame.
  const int reach = std::max(image.width(), image.height()) / 2;
  // Every palette's red has a* of 40 or more (spec section 6); a rise that
  // ends far below that is green meeting black or white, not a tag's centre.
  if (reference_red < kMinRedA) return false;

  // Re-centre on the centroid of the polygon of red/green border points
  // found in eight directions. The paper averages the four axis scans, but
  // on a strongly sheared view (tilt and rotation together) that iteration
  // oscillates instead of converging; the centroid does not.
  bool converged = false;
  for (int iteration = 0; iteration < kMaxCentreIterations && !converged; ++iteration) {
    const float red_thresh = RedGreenThresh(options, reference_red);
    std::vector<cv::Point2f> border(8);
    for (int i = 0; i < 8; ++i) {
      // Red -> green only: the a* drop of the full scan, without the rings.
      const cv::Point2f direction = kDirections[i];
      int consecutive = 0, k = 1;
      for (; k <= reach; ++k) {
        const cv::Point2f p = centre + static_cast<float>(k) * direction;
        const int x = RoundToInt(p.x), y = RoundToInt(p.y);
        if (!image.Contains(x, y)) return false;
        if (reference_red - image.A(x, y) > red_thresh) {
          if (++consecutive == options.border_run) break;
        } else {
          consecutive = 0;
        }
      }
      if (k > reach) return false;
      border[i] = centre + (static_cast<float>(k - options.border_run) + 0.5f) * direction;
    }
    const cv::Moments moments = cv::moments(border);
    if (!(moments.m00 > 0)) return false;
    const cv::Point2f next(static_cast<float>(moments.m10 / moments.m00),
                           static_cast<float>(moments.m01 / moments.m00));
    converged =
        std::abs(next.x - centre.x) < kConvergedPx && std::abs(next.y - centre.y) < kConvergedPx;
    centre = next;
    const int cx = RoundToInt(centre.x);
    const int cy = RoundToInt(centre.y);
    if (!image.Contains(cx, cy)) return false;
    const float centre_red = image.MeanA3x3(cx, cy);
    // The centre of a tag is red: if re-centring left the red, this is not one.
    if (centre_red < reference_red - red_thresh) return false;
    reference_red = centre_red;
  }
  if (!converged) return false;

  candidate->centre = centre;
  candidate->reference_red = reference_red;
  candidate->scan_angles.clear();
  for (auto& ring : candidate->points) ring.clear();
  for (int i = 0; i < 8; i += 2) {
    const cv::Point2f direction = kDirections[i];
    RingHits hits;
    if (!ScanRings(image, options, centre, direction, reference_red, &hits)) return false;
    for (int ring = 0; ring < kNumRings; ++ring)
      candidate->points[ring].push_back(hits.border[ring]);
    candidate->scan_angles.push_back(std::atan2(direction.y, direction.x));
  }
  // Ring widths along each scan: a tag's green and black rings are each one
  // cell, the red half-width one (16h5) or two (36h11) cells. Perspective
  // along one line changes these ratios little.
  for (int i = 0; i < 4; ++i) {
    const float red = cv::norm(candidate->points[kRedGreen][i] - centre);
    const float green =
        cv::norm(candidate->points[kGreenBlack][i] - candidate->points[kRedGreen][i]);
    const float black =
        cv::norm(candidate->points[kBlackWhite][i] - candidate->points[kGreenBlack][i]);
    if (green < 0.2f * red || green > 2.5f * red + 2.f) return false;
    if (black < 0.2f * red || black > 2.5f * red + 2.f) return false;
    if (black < 0.4f * green - 1.f || black > 2.5f * green + 1.f) return false;
  }
  return true;
}

}  // namespace chromatag::internal
