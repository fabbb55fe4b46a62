// Sub-pixel corners, the second half of PolyToQuad. The paper searches a
// patch around each corner with GoodFeaturesToTrack, which returns integer
// pixels (about 2 px off on the authors' own frames). Here each side is
// located instead: along the side, the edge is found on short profiles across
// it where the channel passes halfway between the two neighbouring rings'
// levels; a line is fitted through those edge points, and corners are where
// the lines meet. Blending is linear in the encoded channels used, so the
// halfway point is unbiased for antialiasing and symmetric blur.
#include <algorithm>
#include <array>
#include <cmath>

#include "stages.h"

namespace chromatag::internal {
namespace {

constexpr float kProfileStep = 0.5f;  // Pixels between profile samples.
constexpr int kMaxProfileSteps = 8;   // Samples either side: 4 px.

struct Line {
  cv::Point2d point;
  cv::Point2d direction;
};

// Total least squares line through `points`, then once more without points
// farther than three median residuals (at least half a pixel) from it.
// Works in place (the kept points are moved to the front): it runs for every
// side of every ring, and allocating its scratch cost more than the fit.
bool FitLine(std::vector<cv::Point2d>* points, Line* line) {
  thread_local std::vector<double> residual, sorted;
  for (int pass = 0; pass < 2; ++pass) {
    if (points->size() < 3) return false;
    cv::Point2d c(0, 0);
    for (const auto& p : *points) c += p;
    c *= 1.0 / static_cast<double>(points->size());
    double sxx = 0, sxy = 0, syy = 0;
    for (const auto& p : *points) {
      const cv::Point2d d = p - c;
      sxx += d.x * d.x;
      sxy += d.x * d.y;
      syy += d.y * d.y;
    }
    const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    line->point = c;
    line->direction = {std::cos(angle), std::sin(angle)};
    if (pass == 1) break;
    const cv::Point2d normal(-line->direction.y, line->direction.x);
    residual.clear();
    for (const auto& p : *points) residual.push_back(std::abs((p - c).dot(normal)));
    sorted.assign(residual.begin(), residual.end());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double limit = std::max(0.5, 3.0 * sorted[sorted.size() / 2]);
    size_t kept = 0;
    for (size_t i = 0; i < points->size(); ++i) {
      if (residual[i] <= limit) (*points)[kept++] = (*points)[i];
    }
    points->resize(kept);
  }
  return true;
}

// The edge point on the profile across the side at `middle`, searched within
// `half` pixels either way: the steepest part of the profile is taken as
// roughly the edge, the two levels are read half a cell either side of it,
// and the edge is where the profile passes halfway between them. Reading the
// levels around the edge found, not around the current line, keeps them on
// the plateaus when the line is still a pixel or two off (on small cells),
// so one pass already lands on the edge.
bool EdgePoint(const ImageView& image, const ChannelWeights& channel, int polarity,
               cv::Point2d middle, cv::Point2d outward, double half, double level_offset,
               float min_contrast, cv::Point2d* edge) {
  const int steps = std::min(kMaxProfileSteps, static_cast<int>(std::ceil(half / kProfileStep)));
  const int n = 2 * steps + 1;
  const float mx = static_cast<float>(middle.x), my = static_cast<float>(middle.y);
  const float ox = static_cast<float>(outward.x) * kProfileStep,
              oy = static_cast<float>(outward.y) * kProfileStep;
  std::array<float, 2 * kMaxProfileSteps + 1> profile;
  const float first = static_cast<float>(-steps);
  if (!image.SampleLine(mx + first * ox, my + first * oy, ox, oy, n, channel, profile.data()))
    return false;
  // Steepest: the largest change over one pixel (two samples).
  int steepest = 1;
  float steepest_change = -1.f;
  for (int i = 1; i + 1 < n; ++i) {
    // Only steps the right way round count: the next ring's edge, a cell
    // away, is often steeper (black/white beside green/black).
    const float change = polarity * (profile[i + 1] - profile[i - 1]);
    if (change > steepest_change) {
      steepest_change = change;
      steepest = i;
    }
  }
  if (!(steepest_change > 0.f)) return false;
  const double centre = (steepest - steps) * kProfileStep;
  float inside = 0, outside = 0;
  const cv::Point2d in = middle + (centre - level_offset) * outward;
  const cv::Point2d out = middle + (centre + level_offset) * outward;
  if (!image.Sample(static_cast<float>(in.x), static_cast<float>(in.y), channel, &inside) ||
      !image.Sample(static_cast<float>(out.x), static_cast<float>(out.y), channel, &outside)) {
    return false;
  }
  if (std::abs(outside - inside) < min_contrast) return false;
  const float mid = 0.5f * (inside + outside);
  double best = 1e300;
  for (int i = 1; i < n; ++i) {
    const float previous = profile[i - 1], v = profile[i];
    if ((previous - mid) * (v - mid) <= 0 && previous != v) {
      const double at =
          (i - 1 - steps) * kProfileStep + kProfileStep * (mid - previous) / (v - previous);
      if (std::abs(at - centre) < std::abs(best - centre)) best = at;
    }
  }
  if (best > 1e299) return false;
  *edge = middle + best * outward;
  return true;
}

}  // namespace

bool RefineQuad(const ImageView& image, const SideSearch& search, Quad* quad) {
  const ChannelWeights& channel = search.channel;
  const float min_contrast = search.min_contrast;
  const double cell = search.cell;
  const int max_samples = search.max_samples;
  const double max_half = search.max_half;
  double mean_length = 0;
  for (int i = 0; i < 4; ++i) mean_length += 0.25 * cv::norm((*quad)[(i + 1) % 4] - (*quad)[i]);
  std::array<Line, 4> sides;
  thread_local std::vector<cv::Point2d> points;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = (*quad)[i], q = (*quad)[(i + 1) % 4];
    const double length = cv::norm(q - p);
    const cv::Point2d along = (q - p) / length;
    const cv::Point2d outward(along.y, -along.x);
    // Cells across this side, along its normal, shrink as much as the quad's
    // height over it: at each end, the distance of the neighbouring side's
    // far corner from this side. Under perspective on steep views the two
    // ends differ two-fold and more, so the cell is taken where it is read.
    auto cell_at = [&](const cv::Point2d& far_corner, const cv::Point2d& from) {
      const cv::Point2d v = far_corner - from;
      const double height = std::abs(v.x * along.y - v.y * along.x);
      return cell * std::clamp(height / mean_length, 0.4, 2.5);
    };
    const double cell_p = cell_at((*quad)[(i + 3) % 4], p);
    const double cell_q = cell_at((*quad)[(i + 2) % 4], q);
    const int samples = std::clamp(static_cast<int>(length / 2.0), 5, max_samples);
    points.clear();
    for (int j = 0; j < samples; ++j) {
      // Keep clear of the corners, where the neighbouring side interferes.
      const double t = 0.12 + 0.76 * j / (samples - 1);
      const double local_cell = cell_p + t * (cell_q - cell_p);
      const double level_offset = 0.5 * local_cell;
      const double half = std::clamp(0.5 * local_cell, 1.0, max_half);
      cv::Point2d edge;
      if (EdgePoint(image, channel, search.polarity, p + t * (q - p), outward, half, level_offset,
                    min_contrast, &edge)) {
        points.push_back(edge);
      }
    }
    if (points.size() < 4) return false;
    if (!FitLine(&points, &sides[i])) return false;
  }
  Quad refined;
  for (int i = 0; i < 4; ++i) {
    const Line& a = sides[(i + 3) % 4];
    const Line& b = sides[i];
    if (!IntersectLines(a.point, a.direction, b.point, b.direction, &refined[i])) return false;
    // The refinement moves corners by the scans' error, about a pixel; a large
    // move means a side locked onto another edge.
    if (cv::norm(refined[i] - (*quad)[i]) > std::max(2.0, search.max_move_cells * cell)) {
      return false;
    }
  }
  if (!IsConvexClockwise(refined)) return false;
  *quad = refined;
  return true;
}

bool RefineQuads(const ImageView& image, Candidate* candidate) {
  // One cell: the width of the black ring, between the outer and green quads.
  const double cell = 0.5 * (std::sqrt(QuadArea(candidate->quads[kBlackWhite])) -
                             std::sqrt(QuadArea(candidate->quads[kGreenBlack])));
  if (!(cell > 1.0)) return false;
  // The outer border gives the reported corners and the homography. Edge
  // points do not depend on the line they were searched from (EdgePoint), so
  // one pass usually lands; another, in a narrower window, only when the
  // corners moved more than half a pixel (the polygon was far off: small or
  // strongly tilted tags). Corner error over the test sweep: max 0.16 px with
  // this rule, 0.35 px with one pass always.
  constexpr int kMaxOuterPasses = 3;
  constexpr double kSettledPx = 0.5;
  for (int pass = 0; pass < kMaxOuterPasses; ++pass) {
    const Quad before = candidate->quads[kBlackWhite];
    // The first pass searches up to 4 px either side (the polygon's corners
    // can be that far off); later ones only around the last lines.
    const double max_half = pass == 0 ? 4.0 : 1.5;
    if (!RefineQuad(image, {kGray, kRisesOutwards, kMinGrayContrast, cell, 20, max_half},
                    &candidate->quads[kBlackWhite]))
      return false;
    double moved = 0;
    for (int i = 0; i < 4; ++i)
      moved = std::max(moved, cv::norm(candidate->quads[kBlackWhite][i] - before[i]));
    if (moved < kSettledPx) break;
  }
  if (!RefineQuad(image, {kGray, kFallsOutwards, kMinGreenBlackContrast, cell, 10, 2.5},
                  &candidate->quads[kGreenBlack]))
    return false;
  if (!RefineQuad(image, {kRedMinusGreen, kFallsOutwards, kMinRedGreenContrast, cell, 10, 2.5},
                  &candidate->quads[kRedGreen]))
    return false;
  return true;
}

}  // namespace chromatag::internal
