// Stage 3, BuildPolygon (paper section 4, Figures 6d-g and 7).
#include "build_polygon.h"

#include <algorithm>
#include <cmath>

#include "candidate.h"
#include "geometry.h"
#include "scan_rings.h"

namespace chromatag::internal {
namespace {

constexpr int kMaxScans = 40;
// Two scans closer than this in angle would find the same border points:
// 0.02 radians (about 1.1 degrees), as the cosine between unit directions.
constexpr float kMaxCosApart = 0.9998f;

// Figure 7: the largest area edge i of a convex polygon could still gain
// without breaking convexity is the triangle between the edge and the meeting
// point of its neighbours' extensions. When they do not meet outside (the
// first diamond of four points), the area is bounded instead by a triangle
// as high as half the edge, and the scan goes out from the edge's middle.
struct Potential {
  double area = 0.0;
  cv::Point2d target;  // Where to scan towards.
};

Potential EdgePotential(const std::vector<cv::Point2f>& hull, size_t i) {
  const size_t n = hull.size();
  const cv::Point2d before(hull[(i + n - 1) % n]), p(hull[i]), q(hull[(i + 1) % n]),
      after(hull[(i + 2) % n]);
  const cv::Point2d edge = q - p;
  const double length = cv::norm(edge);
  const cv::Point2d outward(edge.y / length, -edge.x / length);
  cv::Point2d apex;
  const cv::Point2d d1 = p - before, d2 = q - after;
  if (IntersectLines(p, d1, q, d2, &apex) && (apex - p).dot(d1) > 0 && (apex - q).dot(d2) > 0) {
    const cv::Point2d a = q - p, b = apex - p;
    return {0.5 * std::abs(a.x * b.y - a.y * b.x), apex};
  }
  return {0.25 * length * length, 0.5 * (p + q) + 0.5 * length * outward};
}

// How far `point` lies inside the convex polygon (negative outside).
double DepthInside(const std::vector<cv::Point2f>& hull, cv::Point2f point) {
  double depth = 1e300;
  for (size_t i = 0; i < hull.size(); ++i) {
    const cv::Point2d p(hull[i]), q(hull[(i + 1) % hull.size()]);
    const cv::Point2d edge = q - p;
    const cv::Point2d inward(-edge.y, edge.x);
    depth = std::min(depth, (cv::Point2d(point) - p).dot(inward) / cv::norm(inward));
  }
  return depth;
}

bool AlreadyScanned(const std::vector<cv::Point2f>& directions, cv::Point2f direction) {
  for (const cv::Point2f& d : directions) {
    if (d.dot(direction) > kMaxCosApart) return true;
  }
  return false;
}

}  // namespace

bool BuildPolygon(const ImageView& image, const DetectorOptions& options,
                  RingScanBuffers* scan_buffers, PolygonBuffers* buffers, Candidate* candidate,
                  RejectReason* why) {
  auto& outer = candidate->points[kBlackWhite];
  std::vector<cv::Point2f>& hull = buffers->hull;
  for (int scan = 0; scan < kMaxScans; ++scan) {
    ClockwiseHull(outer, &buffers->sorted, &hull);
    if (hull.size() < 3) {
      *why = RejectReason::kPolygonScan;
      return false;
    }
    const double area = PolygonArea(hull);
    double perimeter = 0.0, potential = 0.0;
    double best_area = -1.0;
    cv::Point2f best_direction;
    for (size_t i = 0; i < hull.size(); ++i) {
      perimeter += cv::norm(hull[(i + 1) % hull.size()] - hull[i]);
      const Potential edge = EdgePotential(hull, i);
      potential += edge.area;
      if (edge.area <= best_area) continue;
      const cv::Point2d to = edge.target - cv::Point2d(candidate->centre);
      const double length = std::sqrt(to.dot(to));
      if (!(length > 1e-9)) continue;
      const cv::Point2f direction(static_cast<float>(to.x / length),
                                  static_cast<float>(to.y / length));
      if (!AlreadyScanned(candidate->scan_directions, direction)) {
        best_area = edge.area;
        best_direction = direction;
      }
    }
    // ConvThresh, or nothing left to gain beyond the half-pixel jitter of the
    // border points themselves (which dominates on small tags).
    if (area / (area + potential) > options.conv_thresh || potential < 0.5 * perimeter) {
      return true;
    }
    if (best_area < 0.0) return true;  // Every direction worth scanning was scanned.

    RingHits hits;
    candidate->scan_directions.push_back(best_direction);
    if (!ScanRings(image, options, candidate->centre, best_direction, candidate->reference_red,
                   scan_buffers, &hits)) {
      *why = RejectReason::kPolygonScan;
      return false;
    }
    // A tag's border is convex: a new point well inside the polygon is not
    // on one.
    if (DepthInside(hull, hits.border[kBlackWhite]) > 1.5 + 0.05 * std::sqrt(area)) {
      *why = RejectReason::kNotConvex;
      return false;
    }
    for (int ring = 0; ring < kNumRings; ++ring)
      candidate->points[ring].push_back(hits.border[ring]);
  }
  *why = RejectReason::kPolygonUnfinished;
  return false;
}

}  // namespace chromatag::internal
