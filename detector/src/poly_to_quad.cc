// Stage 4, PolyToQuad (paper section 4, Figure 6h-i): four sides from each
// polygon, then sub-pixel corners (refine_corners.cc).
#include <algorithm>
#include <cmath>

#include "stages.h"

namespace chromatag::internal {
namespace {

constexpr int kSides = 4;
constexpr int kMaxIterations = 10;

double AngleDistance(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 2 * CV_PI);
  return std::min(d, 2 * CV_PI - d);
}

struct Line {
  cv::Point2d point;
  cv::Point2d direction;
};

// Weighted total least squares through the endpoints of a side's edges, each
// endpoint weighted by half its edge's length so that the short edges cutting
// the corners barely count. The paper draws the line at the cluster's mean
// angle through its outer-most point; a fit is less sensitive to one noisy
// point, and the sub-pixel refinement follows anyway.
Line FitSide(const std::vector<cv::Point2f>& hull, const std::vector<int>& label, int side,
             double mean_angle) {
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
  double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  // Keep the clockwise sense of the cluster.
  if (AngleDistance(angle, mean_angle) > CV_PI / 2) angle += CV_PI;
  return {centroid, {std::cos(angle), std::sin(angle)}};
}

// Length-weighted k-means (K = 4) of the hull's edge directions, started
// from the longest edge's direction and its three quarter turns. Angles wrap,
// so the means are of unit vectors.
bool ClusterEdges(const std::vector<cv::Point2f>& hull, std::vector<int>* label,
                  std::array<double, kSides>* centre) {
  const size_t n = hull.size();
  std::vector<double> angle(n), weight(n);
  size_t longest = 0;
  for (size_t i = 0; i < n; ++i) {
    const cv::Point2f e = hull[(i + 1) % n] - hull[i];
    angle[i] = std::atan2(e.y, e.x);
    weight[i] = std::hypot(e.x, e.y);
    if (weight[i] > weight[longest]) longest = i;
  }
  for (int k = 0; k < kSides; ++k) (*centre)[k] = angle[longest] + k * CV_PI / 2;
  label->assign(n, 0);
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      int best = 0;
      for (int k = 1; k < kSides; ++k) {
        if (AngleDistance(angle[i], (*centre)[k]) < AngleDistance(angle[i], (*centre)[best]))
          best = k;
      }
      changed |= (*label)[i] != best;
      (*label)[i] = best;
    }
    std::array<double, kSides> sx{}, sy{};
    for (size_t i = 0; i < n; ++i) {
      sx[(*label)[i]] += weight[i] * std::cos(angle[i]);
      sy[(*label)[i]] += weight[i] * std::sin(angle[i]);
    }
    for (int k = 0; k < kSides; ++k) {
      if (sx[k] == 0 && sy[k] == 0) return false;  // An empty side: not a quad.
      (*centre)[k] = std::atan2(sy[k], sx[k]);
    }
    if (!changed && iteration > 0) break;
  }
  return true;
}

bool FitQuad(const std::vector<cv::Point2f>& points, Quad* quad) {
  if (points.size() < 4) return false;
  const std::vector<cv::Point2f> hull = ClockwiseHull(points);
  if (hull.size() < 4) return false;
  std::vector<int> label;
  std::array<double, kSides> centre;
  if (!ClusterEdges(hull, &label, &centre)) return false;
  // Sides in clockwise order: increasing angle (y points down).
  std::array<int, kSides> order = {0, 1, 2, 3};
  auto unwrapped = [&](int k) {
    double a = centre[k] - centre[0];
    while (a < 0) a += 2 * CV_PI;
    return a;
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return unwrapped(a) < unwrapped(b); });
  std::array<Line, kSides> sides;
  for (int s = 0; s < kSides; ++s) sides[s] = FitSide(hull, label, order[s], centre[order[s]]);
  for (int s = 0; s < kSides; ++s) {
    const Line& a = sides[s];
    const Line& b = sides[(s + 1) % kSides];
    if (!IntersectLines(a.point, a.direction, b.point, b.direction, &(*quad)[(s + 1) % kSides]))
      return false;
  }
  return IsConvexClockwise(*quad);
}

}  // namespace

bool PolyToQuad(const ImageView& image, const DetectorOptions& options, Candidate* candidate,
                RejectReason* why) {
  for (int ring = 0; ring < kNumRings; ++ring) {
    if (!FitQuad(candidate->points[ring], &candidate->quads[ring])) {
      *why = RejectReason::kNoQuad;
      return false;
    }
  }
  // Nested, each ring smaller than the one outside it.
  const double outer = QuadArea(candidate->quads[kBlackWhite]);
  const double green = QuadArea(candidate->quads[kGreenBlack]);
  const double red = QuadArea(candidate->quads[kRedGreen]);
  if (!(red < green && green < outer) || outer < 16.0) {
    *why = RejectReason::kNotNested;
    return false;
  }
  if (options.refine_corners && !RefineQuads(image, candidate)) {
    *why = RejectReason::kRefineFailed;
    return false;
  }
  return true;
}

}  // namespace chromatag::internal
