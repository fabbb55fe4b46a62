// The fast path between InitialScan and PolyToQuad's sub-pixel sides: a
// tag's three quads straight from eight scans through its rings, with the
// side each border point lies on told by the direction of the edge there.
// BuildPolygon (the paper's greedy scans towards the largest potential area,
// about eight more scans and a convex hull after each) remains the way when
// this does not give three plausible quads, or when they fail later on.
#include <algorithm>
#include <array>
#include <cmath>

#include "stages.h"

namespace chromatag::internal {
namespace {

constexpr int kNumScans = 8;  // kScanDirections.
constexpr int kSides = 4;
// A point lies on its side within kOnLinePx plus kOnLineShare of the ring's
// size, and between the side's corners within kCornerSlackPx plus that. A
// side through two or more points needs its ends kMinPairPx apart.
constexpr double kOnLinePx = 1.0;
constexpr double kOnLineShare = 0.02;
constexpr double kCornerSlackPx = 1.5;
constexpr double kMinPairPx = 2.0;
// The sides turn by at least 15 degrees at each corner (the sine): one side
// split in two (when a scan missed a side) does not.
constexpr double kMinCornerTurnSin = 0.26;
// What a side through one point adds to a split's misfit (the sine of an
// edge's angle off its side, summed over the points): about 17 degrees.
constexpr double kLonePenalty = 0.3;
// At most this many of the eight points on one side.
constexpr int kMaxRun = 5;
// An edge runs across its side within 30 degrees (the sine). A point of a
// square's corner-cutting chord (the other quad through the same eight
// points) sees its edge 45 degrees off; measured edge directions wander by
// up to 20-25 degrees under blur, JPEG and noise on small rings.
constexpr double kMaxEdgeAngleSin = 0.5;
// The central differences below must differ by more than this (encoded
// 8-bit units) for an edge direction: about a tenth of the weakest ring
// contrast the sub-pixel sides accept.
constexpr double kMinEdgeGradient = 4.0;

// The outward unit normal of the edge at `p` in `channel` (central
// differences a pixel either side), made to point away from `centre`. False
// where the gradient is too weak to tell or the samples leave the frame.
bool EdgeNormal(const ImageView& image, const ChannelWeights& channel, cv::Point2f p,
                cv::Point2f centre, cv::Point2d* normal) {
  float left, right, up, down;
  if (!image.Sample(p.x - 1.f, p.y, channel, &left) ||
      !image.Sample(p.x + 1.f, p.y, channel, &right) ||
      !image.Sample(p.x, p.y - 1.f, channel, &up) || !image.Sample(p.x, p.y + 1.f, channel, &down))
    return false;
  cv::Point2d g(right - left, down - up);
  const double length = cv::norm(g);
  if (!(length > kMinEdgeGradient)) return false;
  g *= 1.0 / length;
  if (g.dot(cv::Point2d(p - centre)) < 0) g = -g;
  *normal = g;
  return true;
}

struct Line {
  cv::Point2d point;
  cv::Point2d direction;  // Unit.
  double Distance(const cv::Point2d& p) const {
    const cv::Point2d d = p - point;
    return std::abs(d.x * direction.y - d.y * direction.x);
  }
};

// Total least squares line through the points whose bits are set in `mask`
// (at least two): through their mean, along the major axis of their
// scatter (the 2 x 2 eigenvector in closed form; no trigonometry, as this
// runs for every run of points of every ring).
Line FitLine(const std::array<cv::Point2d, kNumScans>& points, unsigned mask) {
  cv::Point2d mean(0, 0);
  int n = 0;
  for (int k = 0; k < kNumScans; ++k) {
    if (mask >> k & 1u) {
      mean += points[k];
      ++n;
    }
  }
  mean *= 1.0 / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (int k = 0; k < kNumScans; ++k) {
    if (!(mask >> k & 1u)) continue;
    const cv::Point2d d = points[k] - mean;
    sxx += d.x * d.x;
    sxy += d.x * d.y;
    syy += d.y * d.y;
  }
  const double half_difference = 0.5 * (sxx - syy);
  const double largest =
      0.5 * (sxx + syy) + std::sqrt(half_difference * half_difference + sxy * sxy);
  // (largest - syy, sxy) and (sxy, largest - sxx) both lie along the axis;
  // the longer is the better conditioned.
  cv::Point2d axis(largest - syy, sxy);
  const cv::Point2d other(sxy, largest - sxx);
  if (other.dot(other) > axis.dot(axis)) axis = other;
  const double length = cv::norm(axis);
  if (!(length > 0)) return {mean, {1, 0}};
  return {mean, axis * (1.0 / length)};
}

// A run of consecutive border points taken as one side.
struct Arc {
  bool valid = false;
  Line line;
  // How far its points' edges are from running across it: the sum of the
  // sines of their angles (a lone point's is 0 by construction).
  double misfit = 0;
};

// One ring's quad from its eight border points (clockwise, one per scan):
// the points split into four runs of consecutive points, one per side, each
// side the line through its run (through a lone point, across its edge
// direction). A run's points must lie on its line, and those inside the run
// (its ends may sit at corners, where the edge turns) must show an edge
// across it. Eight points on a square alone fit two quads when neither has
// a point near a corner (the true one, and the one through the chords that
// cut its corners): the edge directions tell them apart. Of the splits that
// make a convex quad with each point between its side's corners, the one
// whose points' edges run across their sides best, a lone point counting as
// kLonePenalty (its side's direction is its edge's alone).
bool RingQuad(const ImageView& image, const ChannelWeights& channel, cv::Point2f centre,
              const std::array<cv::Point2f, kNumScans>& scanned, Quad* quad) {
  std::array<cv::Point2d, kNumScans> points;
  std::array<cv::Point2d, kNumScans> normal;
  std::array<bool, kNumScans> has_normal;
  for (int k = 0; k < kNumScans; ++k) {
    points[k] = cv::Point2d(scanned[k]);
    has_normal[k] = EdgeNormal(image, channel, scanned[k], centre, &normal[k]);
  }
  // The ring's size sets the tolerance: ScanRings' points are within about
  // a pixel of the border, more on large blurred tags.
  double size = 0;
  for (int k = 0; k < kNumScans / 2; ++k)
    size = std::max(size, cv::norm(points[k] - points[k + kNumScans / 2]));
  const double tolerance = kOnLinePx + kOnLineShare * size;
  auto across = [&](int k, const Line& line) {
    return has_normal[k] && std::abs(normal[k].dot(line.direction)) < kMaxEdgeAngleSin;
  };
  // arcs[first][length - 1]: the run of `length` points from `first`.
  std::array<std::array<Arc, kMaxRun>, kNumScans> arcs;
  for (int first = 0; first < kNumScans; ++first) {
    for (int length = 1; length <= kMaxRun; ++length) {
      Arc& arc = arcs[first][length - 1];
      if (length == 1) {
        if (!has_normal[first]) continue;
        arc.line = {points[first], {-normal[first].y, normal[first].x}};
        arc.valid = true;
        continue;
      }
      unsigned mask = 0;
      for (int j = 0; j < length; ++j) mask |= 1u << ((first + j) % kNumScans);
      const cv::Point2d span = points[(first + length - 1) % kNumScans] - points[first];
      if (!(cv::norm(span) > kMinPairPx)) continue;
      arc.line = FitLine(points, mask);
      if (arc.line.direction.dot(span) < 0) arc.line.direction = -arc.line.direction;
      bool on_line = true, any_across = false, inside_across = true;
      for (int j = 0; j < length; ++j) {
        const int k = (first + j) % kNumScans;
        on_line &= arc.line.Distance(points[k]) < tolerance;
        arc.misfit += has_normal[k] ? std::abs(normal[k].dot(arc.line.direction)) : 1.0;
        any_across |= across(k, arc.line);
        if (j > 0 && j < length - 1) inside_across &= across(k, arc.line);
      }
      arc.valid = on_line && any_across && inside_across;
    }
  }
  double best_misfit = 1e300;
  std::array<int, kSides> best_cut{};
  // Four cuts c0 < c1 < c2 < c3: side s runs from cut s to cut s + 1.
  std::array<int, kSides> cut;
  for (cut[0] = 0; cut[0] < kNumScans; ++cut[0]) {
    for (cut[1] = cut[0] + 1; cut[1] < kNumScans; ++cut[1]) {
      for (cut[2] = cut[1] + 1; cut[2] < kNumScans; ++cut[2]) {
        for (cut[3] = cut[2] + 1; cut[3] < kNumScans; ++cut[3]) {
          std::array<const Arc*, kSides> sides;
          int lone = 0;
          double misfit = 0;
          bool fits = true;
          for (int s = 0; s < kSides && fits; ++s) {
            const int length = s + 1 < kSides ? cut[s + 1] - cut[s] : cut[0] + kNumScans - cut[s];
            fits = length <= kMaxRun && arcs[cut[s]][length - 1].valid;
            if (!fits) break;
            sides[s] = &arcs[cut[s]][length - 1];
            lone += length == 1;
            misfit += sides[s]->misfit;
          }
          misfit += kLonePenalty * lone;
          if (!fits || misfit >= best_misfit) continue;
          // Corner s where side s - 1 meets side s; each point between its
          // side's corners.
          Quad candidate;
          for (int s = 0; s < kSides && fits; ++s) {
            const Line& u = sides[(s + kSides - 1) % kSides]->line;
            const Line& v = sides[s]->line;
            fits = std::abs(u.direction.x * v.direction.y - u.direction.y * v.direction.x) >
                       kMinCornerTurnSin &&
                   IntersectLines(u.point, u.direction, v.point, v.direction, &candidate[s]);
          }
          if (!fits || !IsConvexClockwise(candidate)) continue;
          for (int s = 0; s < kSides && fits; ++s) {
            const cv::Point2d p = candidate[s], q = candidate[(s + 1) % kSides];
            const double length = cv::norm(q - p);
            const cv::Point2d along = (q - p) * (1.0 / length);
            const int end = s + 1 < kSides ? cut[s + 1] : cut[0] + kNumScans;
            for (int k = cut[s]; k < end && fits; ++k) {
              const double t = (points[k % kNumScans] - p).dot(along);
              fits = t > -kCornerSlackPx - tolerance && t < length + kCornerSlackPx + tolerance;
            }
          }
          if (!fits) continue;
          best_misfit = misfit;
          best_cut = cut;
        }
      }
    }
  }
  if (!(best_misfit < 1e300)) return false;
  // A run's end at a corner lies on the next side too: each side of two or
  // more points refitted through the points on its line, its neighbours'
  // ends included.
  std::array<Line, kSides> sides;
  for (int s = 0; s < kSides; ++s) {
    const int first = best_cut[s];
    const int length = s + 1 < kSides ? best_cut[s + 1] - first : best_cut[0] + kNumScans - first;
    sides[s] = arcs[first][length - 1].line;
    if (length == 1) continue;
    unsigned mask = 0;
    for (int j = -1; j <= length; ++j) {
      const int k = (first + j + kNumScans) % kNumScans;
      if (sides[s].Distance(points[k]) < tolerance) mask |= 1u << k;
    }
    sides[s] = FitLine(points, mask);
  }
  Quad refitted;
  for (int s = 0; s < kSides; ++s) {
    const Line& u = sides[(s + kSides - 1) % kSides];
    const Line& v = sides[s];
    if (!IntersectLines(u.point, u.direction, v.point, v.direction, &refitted[s])) return false;
  }
  if (!IsConvexClockwise(refitted)) return false;
  *quad = refitted;
  return true;
}

}  // namespace

bool QuadsFromScans(const ImageView& image, const DetectorOptions& options, Candidate* candidate) {
  // InitialScan leaves the four axis scans (right, down, left, up: the even
  // kScanDirections); the diagonals fill in between.
  if (candidate->points[kBlackWhite].size() != 4) return false;
  std::array<std::array<cv::Point2f, kNumScans>, kNumRings> points;
  for (int ring = 0; ring < kNumRings; ++ring) {
    for (int k = 0; k < 4; ++k) points[ring][2 * k] = candidate->points[ring][k];
  }
  for (int k = 1; k < kNumScans; k += 2) {
    RingHits hits;
    if (!ScanRings(image, options, candidate->centre, kScanDirections[k], candidate->reference_red,
                   &hits))
      return false;
    for (int ring = 0; ring < kNumRings; ++ring) points[ring][k] = hits.border[ring];
  }
  const ChannelWeights channels[kNumRings] = {kRedMinusGreen, kGray, kGray};
  for (int ring = 0; ring < kNumRings; ++ring) {
    if (!RingQuad(image, channels[ring], candidate->centre, points[ring], &candidate->quads[ring]))
      return false;
  }
  return true;
}

}  // namespace chromatag::internal
