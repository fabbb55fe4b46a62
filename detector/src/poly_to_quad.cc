// Stage 4, PolyToQuad (paper section 4, Figure 6h-i): four sides from each
// polygon, then sub-pixel corners (refine_corners.cc).
#include "poly_to_quad.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "candidate.h"
#include "geometry.h"
#include "refine_corners.h"

namespace chromatag::internal {
namespace {

constexpr int kSides = 4;

// Weighted total least squares through the endpoints of a side's edges, each
// endpoint weighted by half its edge's length so that the short edges cutting
// the corners barely count. The paper draws the line at the cluster's mean
// angle through its outer-most point; a fit is less sensitive to one noisy
// point, and the sub-pixel refinement follows anyway.
Line FitSide(const std::vector<cv::Point2f>& hull, const std::vector<int>& label, int side,
             cv::Point2d along) {
  double w_sum = 0, mx = 0, my = 0;
  const size_t n = hull.size();
  auto each_endpoint = [&](auto&& visit) {
    for (size_t i = 0; i < n; ++i) {
      if (label[i] != side) continue;
      const cv::Point2d p(hull[i]), q(hull[(i + 1) % n]);
      const double w = 0.5 * cv::norm(q - p);
      visit(p, w);
      visit(q, w);
    }
  };
  each_endpoint([&](cv::Point2d p, double w) {
    w_sum += w;
    mx += w * p.x;
    my += w * p.y;
  });
  const cv::Point2d centroid(mx / w_sum, my / w_sum);
  double sxx = 0, sxy = 0, syy = 0;
  each_endpoint([&](cv::Point2d p, double w) {
    const cv::Point2d d = p - centroid;
    sxx += w * d.x * d.x;
    sxy += w * d.x * d.y;
    syy += w * d.y * d.y;
  });
  cv::Point2d direction = MajorAxis(sxx, sxy, syy);
  // Keep the clockwise sense of the cluster.
  if (direction.dot(along) < 0) direction = -direction;
  return {centroid, direction};
}

// The four corners of a convex hull (clockwise), as indices into it: vertices
// are dropped one at a time, each time the one whose triangle with its two
// neighbours is smallest (the least area lost), until four remain
// (Visvalingam's simplification). The paper clusters edge directions with
// k-means instead; started from four quarter turns, that fails on views
// whose sides meet at 30 degrees or less (steep tilt with perspective).
bool HullCorners(const std::vector<cv::Point2f>& hull, QuadFitBuffers* buffers,
                 std::array<int, kSides>* corners) {
  const int n = static_cast<int>(hull.size());
  if (n < kSides) return false;
  // A ring of the vertices still kept, with each one's triangle: dropping a
  // vertex changes only its two neighbours' triangles.
  std::vector<int>& prev = buffers->prev;
  std::vector<int>& next = buffers->next;
  std::vector<double>& area = buffers->area;
  prev.resize(n);
  next.resize(n);
  area.resize(n);
  auto triangle = [&](int a, int b, int c) {
    const cv::Point2f u = hull[b] - hull[a], v = hull[c] - hull[b];
    return std::abs(static_cast<double>(u.x) * v.y - static_cast<double>(u.y) * v.x);
  };
  for (int i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  for (int i = 0; i < n; ++i) area[i] = triangle(prev[i], i, next[i]);
  constexpr double kDropped = std::numeric_limits<double>::infinity();
  for (int kept = n; kept > kSides; --kept) {
    int drop = 0;
    for (int i = 1; i < n; ++i) {  // The first smallest, as the vertices go round.
      if (area[i] < area[drop]) drop = i;
    }
    const int before = prev[drop], after = next[drop];
    next[before] = after;
    prev[after] = before;
    area[drop] = kDropped;
    area[before] = triangle(prev[before], before, after);
    area[after] = triangle(before, after, next[after]);
  }
  int k = 0;
  for (int i = 0; i < n && k < kSides; ++i) {
    if (area[i] != kDropped) (*corners)[k++] = i;
  }
  return k == kSides;
}

}  // namespace

bool FitQuad(const std::vector<cv::Point2f>& points, QuadFitBuffers* buffers, Quad* quad) {
  if (points.size() < 4) return false;
  std::vector<cv::Point2f>& hull = buffers->hull;
  ClockwiseHull(points, &buffers->sorted, &hull);
  if (hull.size() < 4) return false;
  std::array<int, kSides> corners;
  if (!HullCorners(hull, buffers, &corners)) return false;
  // Hull edge i (from vertex i to i + 1) lies on side k when it lies between
  // corners k and k + 1; sides run clockwise like the hull.
  const int n = static_cast<int>(hull.size());
  std::vector<int>& label = buffers->label;
  label.assign(n, 0);
  std::array<Line, kSides> sides;
  for (int k = 0; k < kSides; ++k) {
    for (int i = corners[k]; i != corners[(k + 1) % kSides]; i = (i + 1) % n) label[i] = k;
  }
  for (int k = 0; k < kSides; ++k) {
    sides[k] = FitSide(hull, label, k, hull[corners[(k + 1) % kSides]] - hull[corners[k]]);
  }
  return QuadFromSides(sides, quad) && IsConvexClockwise(*quad);
}

bool PolyToQuad(const ImageView& image, const StageSwitches& switches, QuadFitBuffers* fit_buffers,
                SideFitBuffers* side_buffers, Candidate* candidate, RejectReason* why) {
  for (int ring = 0; ring < kNumRings; ++ring) {
    if (!FitQuad(candidate->points[ring], fit_buffers, &candidate->quads[ring])) {
      *why = RejectReason::kNoQuad;
      return false;
    }
  }
  return NestedAndRefined(image, switches, side_buffers, candidate, why);
}

bool NestedAndRefined(const ImageView& image, const StageSwitches& switches,
                      SideFitBuffers* buffers, Candidate* candidate, RejectReason* why) {
  // Nested, each ring smaller than the one outside it.
  const double outer = QuadArea(candidate->quads[kBlackWhite]);
  const double green = QuadArea(candidate->quads[kGreenBlack]);
  const double red = QuadArea(candidate->quads[kRedGreen]);
  if (!(red < green && green < outer) || outer < 16.0) {
    *why = RejectReason::kNotNested;
    return false;
  }
  if (switches.refine_corners && !RefineOuterQuad(image, buffers, candidate)) {
    *why = RejectReason::kRefineFailed;
    return false;
  }
  return true;
}

}  // namespace chromatag::internal
