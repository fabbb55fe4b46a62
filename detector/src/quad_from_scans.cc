// The fast path between InitialScan and PolyToQuad's sub-pixel sides: a
// tag's three quads straight from eight scans through its rings, with the
// side each border point lies on told by the direction of the edge there.
// BuildPolygon (the paper's greedy scans towards the largest potential area,
// about eight more scans and a convex hull after each) remains the way when
// this does not give three plausible quads, or when they fail later on.
#include "quad_from_scans.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "candidate.h"
#include "geometry.h"
#include "scan_rings.h"

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

// A run of consecutive border points taken as one side.
struct Arc {
  enum State { kUnknown, kValid, kInvalid } state = kUnknown;
  Line line;
  // How far its points' edges are from running across it: the sum of the
  // sines of their angles (for a lone point, kLonePenalty instead).
  double misfit = 0;
};

// One ring's border points, their edge directions, and the runs of them
// (arcs), each worked out when first asked for.
class RingPoints {
 public:
  RingPoints(const ImageView& image, const ChannelWeights& channel, cv::Point2f centre,
             const std::array<cv::Point2f, kNumScans>& scanned) {
    for (int k = 0; k < kNumScans; ++k) {
      points_[k] = cv::Point2d(scanned[k]);
      has_normal_[k] = EdgeNormal(image, channel, scanned[k], centre, &normal_[k]);
    }
    // The ring's size sets the tolerance: ScanRings' points are within about
    // a pixel of the border, more on large blurred tags.
    double size = 0;
    for (int k = 0; k < kNumScans / 2; ++k)
      size = std::max(size, cv::norm(points_[k] - points_[k + kNumScans / 2]));
    tolerance_ = kOnLinePx + kOnLineShare * size;
    // Sums over the points twice round (runs wrap), about the first point
    // (small numbers): a run's least-squares line in constant time.
    sums_[0] = {};
    for (int i = 0; i < 2 * kNumScans; ++i) {
      const cv::Point2d d = points_[i % kNumScans] - points_[0];
      sums_[i + 1] = {sums_[i][0] + d.x, sums_[i][1] + d.y, sums_[i][2] + d.x * d.x,
                      sums_[i][3] + d.x * d.y, sums_[i][4] + d.y * d.y};
    }
  }

  const cv::Point2d& point(int k) const { return points_[k % kNumScans]; }
  double tolerance() const { return tolerance_; }

  // The run of `length` points from `first`, or nullptr if it cannot be a
  // side: its points off its line, or (but for its ends, which may sit at
  // corners) with edges that do not run across it, or none that does.
  const Arc* Run(int first, int length) {
    Arc& arc = arcs_[first][length - 1];
    if (arc.state == Arc::kUnknown) arc.state = Evaluate(first, length, &arc);
    return arc.state == Arc::kValid ? &arc : nullptr;
  }

  // The total least squares line through the run of `length` points from
  // `first`: through their mean, along the major axis of their scatter (the
  // 2 x 2 eigenvector in closed form), pointing from the first to the last.
  bool Fit(int first, int length, Line* line) const {
    first %= kNumScans;
    const auto& hi = sums_[first + length];
    const auto& lo = sums_[first];
    const double n = length;
    const double mx = (hi[0] - lo[0]) / n, my = (hi[1] - lo[1]) / n;
    const double sxx = hi[2] - lo[2] - n * mx * mx, sxy = hi[3] - lo[3] - n * mx * my,
                 syy = hi[4] - lo[4] - n * my * my;
    if (!(sxx + syy > 0)) return false;
    cv::Point2d axis = MajorAxis(sxx, sxy, syy);
    if (axis.dot(point(first + length - 1) - points_[first]) < 0) axis = -axis;
    *line = {points_[0] + cv::Point2d(mx, my), axis};
    return true;
  }

 private:
  bool Across(int k, const Line& line) const {
    return has_normal_[k] && std::abs(normal_[k].dot(line.direction)) < kMaxEdgeAngleSin;
  }

  Arc::State Evaluate(int first, int length, Arc* arc) const {
    if (length == 1) {
      if (!has_normal_[first]) return Arc::kInvalid;
      arc->line = {points_[first], {-normal_[first].y, normal_[first].x}};
      arc->misfit = kLonePenalty;
      return Arc::kValid;
    }
    const cv::Point2d span = point(first + length - 1) - points_[first];
    if (!(span.dot(span) > kMinPairPx * kMinPairPx)) return Arc::kInvalid;
    if (!Fit(first, length, &arc->line)) return Arc::kInvalid;
    const cv::Point2d axis = arc->line.direction;
    bool any_across = false;
    for (int j = 0; j < length; ++j) {
      const int k = (first + j) % kNumScans;
      if (!(arc->line.Distance(points_[k]) < tolerance_)) return Arc::kInvalid;
      const bool across = Across(k, arc->line);
      if (!across && j > 0 && j < length - 1) return Arc::kInvalid;
      any_across |= across;
      arc->misfit += has_normal_[k] ? std::abs(normal_[k].dot(axis)) : 1.0;
    }
    return any_across ? Arc::kValid : Arc::kInvalid;
  }

  std::array<cv::Point2d, kNumScans> points_;
  std::array<cv::Point2d, kNumScans> normal_;
  std::array<bool, kNumScans> has_normal_;
  double tolerance_ = 0;
  std::array<std::array<double, 5>, 2 * kNumScans + 1> sums_;
  std::array<std::array<Arc, kMaxRun>, kNumScans> arcs_;
};

// Four cuts c0 < c1 < c2 < c3 among the eight points: side s is the run
// from cut s up to cut s + 1 (round to c0 + 8 for the last).
using Cuts = std::array<int, kSides>;

int RunLength(const Cuts& cut, int s) {
  return s + 1 < kSides ? cut[s + 1] - cut[s] : cut[0] + kNumScans - cut[s];
}

// The quad of a split, and its misfit; false if it cannot be one (or its
// misfit is not under `worst_misfit`): a run that
// cannot be a side, sides that turn too little at a corner, a quad that is
// not convex, or a point beyond its side's corners.
bool SplitQuad(RingPoints& ring, const Cuts& cut, double worst_misfit, double* misfit,
               std::array<Line, kSides>* sides, Quad* quad) {
  *misfit = 0;
  for (int s = 0; s < kSides; ++s) {
    const int length = RunLength(cut, s);
    if (length > kMaxRun) return false;
    const Arc* arc = ring.Run(cut[s], length);
    if (!arc) return false;
    (*sides)[s] = arc->line;
    *misfit += arc->misfit;
    if (!(*misfit < worst_misfit)) return false;
  }
  for (int s = 0; s < kSides; ++s) {
    const cv::Point2d u = (*sides)[(s + kSides - 1) % kSides].direction, v = (*sides)[s].direction;
    if (!(std::abs(u.x * v.y - u.y * v.x) > kMinCornerTurnSin)) return false;
  }
  if (!QuadFromSides(*sides, quad) || !IsConvexClockwise(*quad)) return false;
  const double slack = kCornerSlackPx + ring.tolerance();
  for (int s = 0; s < kSides; ++s) {
    const cv::Point2d p = (*quad)[s], q = (*quad)[(s + 1) % kSides];
    const double length = cv::norm(q - p);
    const cv::Point2d along = (q - p) * (1.0 / length);
    for (int j = 0; j < RunLength(cut, s); ++j) {
      const double t = (ring.point(cut[s] + j) - p).dot(along);
      if (t < -slack || t > length + slack) return false;
    }
  }
  return true;
}

// One ring's quad from its eight border points (clockwise, one per scan):
// the points split into four runs of consecutive points, one per side, each
// side the line through its run (through a lone point, across its edge
// direction). A run's points must lie on its line, and those inside the run
// (its ends may sit at corners, where the edge turns) must show an edge
// across it. Eight points on a square alone fit two quads when neither has
// a point near a corner (the true one, and the one through the chords that
// cut its corners): the edge directions tell them apart. `hint` (the outer
// ring's split, which the inner rings' scans mostly share) is taken if it
// makes a quad; otherwise, of the splits that do, the one whose points'
// edges run across their sides best.
bool RingQuad(RingPoints& ring, const Cuts* hint, Cuts* used, Quad* quad) {
  double misfit = 0;
  std::array<Line, kSides> sides, tried;
  Quad candidate;
  bool found = hint && SplitQuad(ring, *hint, 1e300, &misfit, &sides, &candidate);
  Cuts cut = hint ? *hint : Cuts{};
  if (!found) {
    double best = 1e300;
    Cuts c;
    for (c[0] = 0; c[0] < kNumScans; ++c[0]) {
      for (c[1] = c[0] + 1; c[1] < kNumScans; ++c[1]) {
        for (c[2] = c[1] + 1; c[2] < kNumScans; ++c[2]) {
          for (c[3] = c[2] + 1; c[3] < kNumScans; ++c[3]) {
            if (SplitQuad(ring, c, best, &misfit, &tried, &candidate)) {
              best = misfit;
              cut = c;
              sides = tried;
            }
          }
        }
      }
    }
    if (!(best < 1e300)) return false;
  }
  // A run's end at a corner lies on the next side too: each side of two or
  // more points refitted through its run and the neighbouring runs' ends
  // that lie on it.
  for (int s = 0; s < kSides; ++s) {
    int first = cut[s] + kNumScans, length = RunLength(cut, s);
    if (length == 1) continue;
    if (sides[s].Distance(ring.point(first - 1)) < ring.tolerance()) --first, ++length;
    if (sides[s].Distance(ring.point(first + length)) < ring.tolerance()) ++length;
    Line refitted;
    if (length < kNumScans && ring.Fit(first, length, &refitted)) sides[s] = refitted;
  }
  if (!QuadFromSides(sides, &candidate) || !IsConvexClockwise(candidate)) return false;
  *used = cut;
  *quad = candidate;
  return true;
}

}  // namespace

bool QuadsFromScans(const ImageView& image, const DetectorOptions& options,
                    RingScanBuffers* buffers, Candidate* candidate) {
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
                   buffers, &hits))
      return false;
    for (int ring = 0; ring < kNumRings; ++ring) points[ring][k] = hits.border[ring];
  }
  // The outer ring first: its edges are the strongest, and its split is the
  // inner rings' first guess.
  const ChannelWeights channels[kNumRings] = {kRedMinusGreen, kGray, kGray};
  Cuts outer_cut;
  for (int ring : {kBlackWhite, kGreenBlack, kRedGreen}) {
    RingPoints ring_points(image, channels[ring], candidate->centre, points[ring]);
    Cuts used;
    if (!RingQuad(ring_points, ring == kBlackWhite ? nullptr : &outer_cut, &used,
                  &candidate->quads[ring]))
      return false;
    if (ring == kBlackWhite) outer_cut = used;
  }
  return true;
}

}  // namespace chromatag::internal
