// Stage 2, InitialScan (paper section 4, Figure 6a-c).
#include "initial_scan.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "candidate.h"
#include "geometry.h"
#include "scan_rings.h"

namespace chromatag::internal {
namespace {

constexpr int kMaxCentreIterations = 8;
// The centre counts as settled when a pass moves it less than this on each
// axis. The final scans start from it and the outer quad's corners are found
// on their own edges, so a centre within a few pixels serves; 0.75 px took a
// pass or two more on most tags (3.3 passes of eight scans on average). On the
// camera set's first 1,500 frames 2.5 px found 813 tags instead of 808 (the
// classic set's 924 instead of 921), every ID right, the outer corners'
// median error 0.85 px as before.
constexpr float kConvergedPx = 2.5f;
// The axis directions (kScanDirections) whose rings are checked after the
// first centring pass, to drop red things that are not tags early: right and
// down, which dropped 2,246 of the 2,645 candidates the four axes dropped
// there on those frames. The final scans check all four.
constexpr int kEarlyRingDirections[] = {0, 2};

// The order of CentringPass's scans. They are independent, so the order
// changes only how soon a candidate that fails is dropped: up first, since
// FindADiff meets a red region on the first sampled row that crosses it, near
// its top, so the upward scan is short and reaches what borders the red
// there (a tag's green, something else for most red things); then the other
// axes, then the diagonals. On the camera set's first 600 frames: 20 % fewer
// pixels walked and InitialScan 4.7 % faster than in index order, the same
// detections.
constexpr int kCentringOrder[8] = {6, 2, 4, 0, 5, 7, 3, 1};
// Pixels past a red/green run searched for the green's full a* drop.
constexpr int kGreenLookAhead = 6;
// A run past the red threshold whose lowest a* stays within this many
// thresholds of ReferenceRed is a dip inside the red, not its border; a scan
// goes past at most kMaxRedDips of them (CentringPass).
constexpr float kRedDipDepth = 2.f;
constexpr int kMaxRedDips = 4;
// The a* drop into a tag's green, as a fraction of ADiffThresh: the palettes'
// reds and greens are 58 or more apart; a fifth less allows for blur and casts.
constexpr float kMinGreenDropFraction = 0.8f;
// Ring widths along one scan (RingProportionsFit): a tag's green and black
// rings are one cell each, its red half-width one (16h5) or two (36h11)
// cells; perspective along one line changes these ratios little. Each ring
// lies between kMinRingOverRed and kMaxRingOverRed times the red half-width
// (plus kRingSlackPx for blur on small tags), and black over green between
// kMinBlackOverGreen and kMaxBlackOverGreen (each with a pixel of slack).
constexpr float kMinRingOverRed = 0.2f;
constexpr float kMaxRingOverRed = 2.5f;
constexpr float kRingSlackPx = 2.f;
constexpr float kMinBlackOverGreen = 0.4f;
constexpr float kMaxBlackOverGreen = 2.5f;
// A rejected region is its red/green border grown about its centre by this
// share of each point's distance plus a margin in pixels: the seeds of later
// rows lie on the region's left edge, where the octagon's sides cut inside.
constexpr float kRejectedRegionGrowth = 0.15f;
constexpr float kRejectedRegionMarginPx = 2.f;

// CentringPass's scan along one direction: from step *k on, to the end of
// the first run of M pixels whose a* lies more than `red_thresh` below
// ReferenceRed. Leaves *k on the run's last pixel and *deepest_a at the run's
// lowest a*, followed a few pixels on where the run ends on a blurred slope.
// False (and *why) when the scan leaves the frame or its reach first.
bool NextRedRun(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                cv::Point2f direction, float reference_red, float red_thresh, int reach, int* k,
                float* deepest_a, RejectReason* why) {
  const float clearly_inside =
      reference_red - red_thresh + static_cast<float>(ColorTable::kCoarseErrorBound);
  int consecutive = 0;
  *deepest_a = reference_red;
  for (; *k <= reach; ++*k) {
    // Outside a run, the pixels clearly short of the threshold change
    // nothing below: passed over eight at a time.
    if (consecutive == 0) {
      *k = image.FirstNotClearlyAbove(centre.x, centre.y, direction.x, direction.y, *k, reach,
                                      clearly_inside);
      if (*k > reach) break;
    }
    const cv::Point2f p = centre + static_cast<float>(*k) * direction;
    const int x = RoundToInt(p.x), y = RoundToInt(p.y);
    if (!image.Contains(x, y)) break;
    // Clearly short of the threshold by the coarse a*: the exact one is
    // not needed (as in ScanBorder).
    if (static_cast<float>(image.CoarseA(x, y)) > clearly_inside) {
      consecutive = 0;
      *deepest_a = reference_red;
      continue;
    }
    const float a = image.A(x, y);
    if (reference_red - a > red_thresh) {
      *deepest_a = std::min(*deepest_a, a);
      if (++consecutive == options.border_run) {
        // On a blurred edge the run may end on the slope: look a few pixels on.
        for (int j = *k + 1; j <= *k + kGreenLookAhead; ++j) {
          const cv::Point2f q = centre + static_cast<float>(j) * direction;
          const int qx = RoundToInt(q.x), qy = RoundToInt(q.y);
          if (!image.Contains(qx, qy)) break;
          *deepest_a = std::min(*deepest_a, image.A(qx, qy));
        }
        return true;
      }
    } else {
      consecutive = 0;
      *deepest_a = reference_red;
    }
  }
  *why = RejectReason::kNoRedGreenBorder;
  return false;
}

// Step 1: the red/green border in the eight directions from `centre`, into
// `border`. False (and *why) when a scan leaves the frame or reach, or finds
// no tag green past the red.
bool CentringPass(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                  float reference_red, int reach, std::array<cv::Point2f, 8>* border,
                  RejectReason* why) {
  const float red_thresh = RedGreenThresh(options, reference_red);
  const float min_drop = kMinGreenDropFraction * static_cast<float>(options.adiff_thresh);
  const float max_green_a = static_cast<float>(options.max_green_a);
  for (int i : kCentringOrder) {
    // Red -> green only: the a* drop of the full scan, without the rings.
    const cv::Point2f direction = kScanDirections[i];
    int k = 1;
    for (int dips = 0;; ++dips) {
      float deepest_a = 0;
      if (!NextRedRun(image, options, centre, direction, reference_red, red_thresh, reach, &k,
                      &deepest_a, why)) {
        return false;
      }
      // Past the border lies a tag's green: far less red than its red, and
      // green (a* below DetectorOptions::max_green_a). Most red things that
      // are not tags (bricks, skin, wood, a red sign on a wall) meet grey,
      // white or black here and are dropped after one scan instead of eight
      // per pass.
      if (reference_red - deepest_a >= min_drop && deepest_a < max_green_a) break;
      // A run that stays within kRedDipDepth thresholds of the red is a dip
      // inside it, not a border: the sensor noise of a dim frame (a* from 15
      // to 29 across one red cell at L* 21) makes runs of M pixels below the
      // threshold. The scan goes on past it.
      if (dips == kMaxRedDips || reference_red - deepest_a >= kRedDipDepth * red_thresh) {
        *why = RejectReason::kNotGreen;
        return false;
      }
      ++k;
    }
    (*border)[i] = centre + (static_cast<float>(k - options.border_run) + 0.5f) * direction;
  }
  return true;
}

// Step 3: whether the ring widths along each of the final scans fit a tag.
bool RingProportionsFit(const Candidate& candidate) {
  for (size_t i = 0; i < candidate.points[kRedGreen].size(); ++i) {
    const float red = cv::norm(candidate.points[kRedGreen][i] - candidate.centre);
    const float green = cv::norm(candidate.points[kGreenBlack][i] - candidate.points[kRedGreen][i]);
    const float black =
        cv::norm(candidate.points[kBlackWhite][i] - candidate.points[kGreenBlack][i]);
    if (green < kMinRingOverRed * red || green > kMaxRingOverRed * red + kRingSlackPx ||
        black < kMinRingOverRed * red || black > kMaxRingOverRed * red + kRingSlackPx ||
        black < kMinBlackOverGreen * green - 1.f || black > kMaxBlackOverGreen * green + 1.f) {
      return false;
    }
  }
  return true;
}

}  // namespace

RejectedRegion RejectedRegion::Around(const std::array<cv::Point2f, 8>& red_border) {
  RejectedRegion region;
  const cv::Point2f middle = PolygonCentroid(red_border);
  for (int i = 0; i < 8; ++i) {
    const cv::Point2f out = red_border[i] - middle;
    const float length = std::sqrt(out.dot(out));
    region.border[i] =
        length > 1e-3f && std::isfinite(length)
            ? red_border[i] +
                  out * ((kRejectedRegionGrowth * length + kRejectedRegionMarginPx) / length)
            : red_border[i];
  }
  region.min_x = region.max_x = region.border[0].x;
  region.min_y = region.max_y = region.border[0].y;
  for (const cv::Point2f& p : region.border) {
    region.min_x = std::min(region.min_x, p.x);
    region.max_x = std::max(region.max_x, p.x);
    region.min_y = std::min(region.min_y, p.y);
    region.max_y = std::max(region.max_y, p.y);
  }
  return region;
}

bool RejectedRegion::BorderContains(cv::Point2f p) const {
  bool inside = false;
  for (size_t i = 0, j = border.size() - 1; i < border.size(); j = i++) {
    const cv::Point2f& a = border[i];
    const cv::Point2f& b = border[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
      inside = !inside;
  }
  return inside;
}

bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed,
                 RingScanBuffers* buffers, Candidate* candidate,
                 std::vector<RejectedRegion>* rejected, RejectReason* why) {
  cv::Point2f centre(static_cast<float>(seed.x), static_cast<float>(seed.y));
  candidate->centre = centre;
  candidate->enclosed = false;
  for (auto& ring : candidate->points) ring.clear();
  // Red things that are not tags span many of FindADiff's rows, and each row
  // seeds them again: a seed inside a region already rejected in this frame
  // would be rejected again.
  if (rejected) {
    for (const RejectedRegion& region : *rejected) {
      if (region.Contains(centre)) {
        *why = RejectReason::kInRejectedRegion;
        return false;
      }
    }
  }
  // The seed may sit on the blurred edge of the red; the reddest of it and
  // its neighbourhood is the better ReferenceRed.
  float reference_red = std::max(image.A(seed.x, seed.y), image.MeanA3x3(seed.x, seed.y));
  RejectedRegion region;
  bool have_region = false;
  std::array<cv::Point2f, 8> border;
  // Leaves the last centre and red/green border in the candidate, for
  // DetectionResult::rejected.
  auto reject = [&](RejectReason reason) {
    if (rejected && have_region) rejected->push_back(region);
    candidate->centre = centre;
    candidate->reference_red = reference_red;
    if (have_region) {
      candidate->points[kRedGreen].assign(border.begin(), border.end());
      candidate->enclosed = true;
      candidate->red_border = border;
    }
    *why = reason;
    return false;
  };
  // A tag's red half-width is under half the frame unless the tag is larger
  // than the frame.
  const int reach = std::max(image.width(), image.height()) / 2;
  if (reference_red < static_cast<float>(kMinTagRedA)) return reject(RejectReason::kPaleRed);

  // Step 1, repeated: re-centre on the centroid of the polygon of red/green
  // border points found in eight directions. The paper averages the four axis scans, but
  // on a strongly sheared view (tilt and rotation together) that iteration
  // oscillates instead of converging; the centroid does not.
  bool converged = false;
  for (int iteration = 0; iteration < kMaxCentreIterations && !converged; ++iteration) {
    const float red_thresh = RedGreenThresh(options, reference_red);
    RejectReason pass_why;
    if (!CentringPass(image, options, centre, reference_red, reach, &border, &pass_why))
      return reject(pass_why);
    region = RejectedRegion::Around(border);
    have_region = true;
    const cv::Point2f next = PolygonCentroid(border);
    if (!(std::isfinite(next.x) && std::isfinite(next.y)))
      return reject(RejectReason::kNoRedGreenBorder);
    converged =
        std::abs(next.x - centre.x) < kConvergedPx && std::abs(next.y - centre.y) < kConvergedPx;
    centre = next;
    // The clamping overload: the centroid of a nearly flat polygon can be
    // anywhere.
    const int cx = RoundToInt(static_cast<double>(centre.x));
    const int cy = RoundToInt(static_cast<double>(centre.y));
    if (!image.Contains(cx, cy)) return reject(RejectReason::kCentreNotRed);
    const float centre_red = image.MeanA3x3(cx, cy);
    // The centre of a tag is red: if re-centring left the red, this is not one.
    if (centre_red < reference_red - red_thresh) return reject(RejectReason::kCentreNotRed);
    reference_red = centre_red;
    // After the first pass the centre lies well inside the red region, and a
    // tag shows all three rings from there in each axis direction (the final
    // scans below ask the same of the converged centre, in all four). Red
    // things that are not tags (sweets, paint, skin next to something green)
    // rarely do, and are dropped here instead of after several more passes of
    // eight scans.
    if (iteration == 0 && !converged) {
      for (int i : kEarlyRingDirections) {
        RingHits hits;
        if (!ScanRings(image, options, centre, kScanDirections[i], reference_red, buffers, &hits))
          return reject(RejectReason::kRingScan);
      }
    }
  }
  if (!converged) return reject(RejectReason::kNoConvergence);

  candidate->centre = centre;
  candidate->reference_red = reference_red;
  candidate->enclosed = true;
  candidate->red_border = border;
  // Step 2: the three rings in the four axis directions from the converged
  // centre seed the candidate's polygons.
  candidate->scan_directions.clear();
  for (int i = 0; i < 8; i += 2) {
    const cv::Point2f direction = kScanDirections[i];
    RingHits hits;
    if (!ScanRings(image, options, centre, direction, reference_red, buffers, &hits))
      return reject(RejectReason::kRingScan);
    for (int ring = 0; ring < kNumRings; ++ring)
      candidate->points[ring].push_back(hits.border[ring]);
    candidate->scan_directions.push_back(direction);
  }
  if (!RingProportionsFit(*candidate)) return reject(RejectReason::kRingProportions);
  return true;
}

}  // namespace chromatag::internal
