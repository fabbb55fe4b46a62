// Sub-pixel corners, the second half of PolyToQuad. The paper searches a
// patch around each corner with GoodFeaturesToTrack, which returns integer
// pixels (about 2 px off on the authors' own frames). Here each side is
// located instead: along the side, the edge is found on short profiles across
// it where the channel passes halfway between the two neighbouring rings'
// levels; a line is fitted through those edge points, and corners are where
// the lines meet. Blending is linear in the encoded channels used, so the
// halfway point is unbiased for antialiasing and symmetric blur.
//
// Only the outer (black/white) border is located this way on every
// candidate: it is the strongest edge, in luminance, which cameras and JPEG
// keep at full resolution. The inner borders are located only when their
// rough quads fit no family (Decode's ring proportions); a detection's inner
// corners are placed from its outer ones (decode.cc says why).
#include "refine_corners.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "candidate.h"
#include "geometry.h"
#include "kernels/kernels.h"
#include "kernels/scalar.h"

namespace chromatag::internal {

bool FitLine(std::vector<cv::Point2d>* points, std::vector<double>* residual_buffer,
             std::vector<double>* sorted_buffer, Line* line) {
  std::vector<double>& residual = *residual_buffer;
  std::vector<double>& sorted = *sorted_buffer;
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
    line->point = c;
    line->direction = MajorAxis(sxx, sxy, syy);
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

namespace {

constexpr int kMinProfiles = 5;             // Per side, however short.
constexpr int kReportedOuterProfiles = 10;  // Per side, for the reported corners.

// The uncertainty of `line`, fitted to `points` (at least three): the
// residuals' variance (two degrees of freedom taken by the fit) over the
// points for the offset at their centroid, over their spread along the line
// for the angle.
SideFit SideFitOf(const std::vector<cv::Point2d>& points, const Line& line) {
  const cv::Point2d normal(-line.direction.y, line.direction.x);
  double sum_r2 = 0, sum_u2 = 0;
  for (const auto& p : points) {
    const cv::Point2d d = p - line.point;
    sum_r2 += d.dot(normal) * d.dot(normal);
    sum_u2 += d.dot(line.direction) * d.dot(line.direction);
  }
  const double n = static_cast<double>(points.size());
  const double variance = points.size() > 2 ? sum_r2 / (n - 2.0) : 0.0;
  SideFit fit;
  fit.line = line;
  fit.offset_variance = variance / n;
  fit.angle_variance = sum_u2 > 0 ? variance / sum_u2 : 0.0;
  return fit;
}

}  // namespace

cv::Matx<double, 8, 8> CornerCovariance(const std::array<SideFit, 4>& sides, const Quad& quad) {
  // Corner i moves with the sides through it: along side a's normal by a's
  // offset error plus its angle error times the corner's distance along a
  // from a's centroid; likewise for b. g maps the eight side errors
  // (offset, angle of side 0, then side 1, ...) to the corners' x, y.
  cv::Matx<double, 8, 8> g = cv::Matx<double, 8, 8>::zeros();
  for (int i = 0; i < 4; ++i) {
    const int side[2] = {(i + 3) % 4, i};
    cv::Matx22d normals;
    cv::Matx<double, 2, 8> moves = cv::Matx<double, 2, 8>::zeros();
    for (int k = 0; k < 2; ++k) {
      const Line& line = sides[side[k]].line;
      normals(k, 0) = -line.direction.y;
      normals(k, 1) = line.direction.x;
      moves(k, 2 * side[k]) = 1.0;
      moves(k, 2 * side[k] + 1) = (quad[i] - line.point).dot(line.direction);
    }
    const cv::Matx<double, 2, 8> rows = normals.inv() * moves;
    for (int c = 0; c < 8; ++c) {
      g(2 * i, c) = rows(0, c);
      g(2 * i + 1, c) = rows(1, c);
    }
  }
  cv::Matx<double, 8, 8> errors = cv::Matx<double, 8, 8>::zeros();
  for (int k = 0; k < 4; ++k) {
    errors(2 * k, 2 * k) = sides[k].offset_variance;
    errors(2 * k + 1, 2 * k + 1) = sides[k].angle_variance;
  }
  return g * errors * g.t();
}

cv::Vec<double, 8> QuadGrowth(const Quad& quad) {
  const cv::Point2d centre = 0.25 * (quad[0] + quad[1] + quad[2] + quad[3]);
  cv::Vec<double, 8> grow;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d out = quad[i] - centre;
    const double length = std::max(cv::norm(out), 1e-9);
    grow[2 * i] = out.x / length;
    grow[2 * i + 1] = out.y / length;
  }
  return grow;
}

cv::Matx<double, 8, 8> ReportedCornerCovariance(const std::array<SideFit, 4>& sides,
                                                const Quad& encoded, const Quad& linear) {
  using Matx88 = cv::Matx<double, 8, 8>;
  using Vec8 = cv::Vec<double, 8>;
  const CornerNoiseModel& m = kCornerNoise;
  // How far apart the two conventions put each corner, and each side (along
  // its normal): the edge's width shows in it, and a motion blur widens the
  // sides across the motion only.
  Vec8 apart;
  double side_min = std::numeric_limits<double>::infinity(), side_max = 0.0;
  for (int i = 0; i < 4; ++i) {
    apart[2 * i] = linear[i].x - encoded[i].x;
    apart[2 * i + 1] = linear[i].y - encoded[i].y;
    const cv::Point2d normal(-sides[i].line.direction.y, sides[i].line.direction.x);
    const cv::Point2d moved =
        0.5 * (linear[i] - encoded[i] + linear[(i + 1) % 4] - encoded[(i + 1) % 4]);
    const double side = std::abs(moved.dot(normal));
    side_min = std::min(side_min, side);
    side_max = std::max(side_max, side);
  }
  const double uneven = side_max - side_min;
  const Vec8 shift_x = kQuadShiftX, shift_y = kQuadShiftY, grow = QuadGrowth(linear);
  const auto sq = [](double v) { return v * v; };
  return sq(m.scatter) * CornerCovariance(sides, linear) + sq(m.share) * apart * apart.t() +
         (sq(m.floor_px) + sq(m.uneven_each * uneven)) * Matx88::eye() +
         sq(m.uneven_shift * uneven) * (shift_x * shift_x.t() + shift_y * shift_y.t()) +
         sq(m.grow_px) * grow * grow.t();
}

// The edge point on the profile across the side at `middle`, searched within
// `half` pixels either way: the steepest part of the profile is taken as
// roughly the edge, the two levels are read half a cell either side of it,
// and the edge is where the profile passes halfway between them. Reading the
// levels around the edge found, not around the current line, keeps them on
// the plateaus when the line is still a pixel or two off (on small cells),
// so one pass already lands on the edge.
bool EdgePoint(const ImageView& image, const ChannelWeights& channel, int polarity,
               const ProfileSpec& spec, float min_contrast, cv::Point2d* edge, Halfway halfway) {
  // In linear light (the gray channel only), the profile and the two levels
  // are decoded before the halfway crossing is sought; the levels must still
  // differ by `min_contrast` in encoded values.
  const bool linear =
      halfway == Halfway::kLinearLight && channel.r == 1 && channel.g == 1 && channel.b == 1;
  const cv::Point2d middle = spec.middle, outward = spec.outward;
  const double half = spec.half, level_offset = spec.level_offset;
  // In double until bounded: a degenerate side could make `half` huge.
  const int steps =
      static_cast<int>(std::min<double>(kMaxProfileSteps, std::ceil(half / kProfileStep)));
  const int n = 2 * steps + 1;
  const float mx = static_cast<float>(middle.x), my = static_cast<float>(middle.y);
  const float ox = static_cast<float>(outward.x) * kProfileStep,
              oy = static_cast<float>(outward.y) * kProfileStep;
  std::array<float, 2 * kMaxProfileSteps + 1> profile;
  const float first = static_cast<float>(-steps);
  if (!image.SampleLine(mx + first * ox, my + first * oy, ox, oy, n, channel, profile.data()))
    return false;
  if (linear) {
    for (int i = 0; i < n; ++i) profile[i] = LinearGray(profile[i]);
  }
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
  const float mid =
      linear ? 0.5f * (LinearGray(inside) + LinearGray(outside)) : 0.5f * (inside + outside);
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

void EdgePoints(const ImageView& image, const ChannelWeights& channel, int polarity,
                const ProfileSpec* spec, int count, float min_contrast, ProfileEdge* out,
                Halfway halfway) {
  int done = 0;
  const bool gray = channel.r == 1 && channel.g == 1 && channel.b == 1;
  const bool red_minus_green = channel.r == 1 && channel.g == -1 && channel.b == 0;
  const bool linear = gray && halfway == Halfway::kLinearLight;
  const Kernels& kernels = image.kernels();
  if (kernels.edge_points8 && (gray || red_minus_green) && image.OffsetsFit32()) {
    for (; done < count; done += 8) {
      // The profiles the kernel leaves over, one by one.
      unsigned left_over =
          kernels.edge_points8(image.frame(), gray, polarity, spec + done,
                               std::min(8, count - done), min_contrast, out + done, linear);
      for (; left_over; left_over &= left_over - 1) {
        const int l = done + __builtin_ctz(left_over);
        out[l].found =
            EdgePoint(image, channel, polarity, spec[l], min_contrast, &out[l].edge, halfway);
      }
    }
  }
  for (; done < count; ++done) {
    out[done].found =
        EdgePoint(image, channel, polarity, spec[done], min_contrast, &out[done].edge, halfway);
  }
}

namespace {

// The profiles across the four sides of `quad` for `search`: side i's are
// spec[first[i] .. first[i + 1]).
void SideProfiles(const Quad& quad, const SideSearch& search, std::vector<ProfileSpec>* spec,
                  std::array<int, 5>* first) {
  const double cell = search.cell;
  double mean_length = 0;
  for (int i = 0; i < 4; ++i) mean_length += 0.25 * cv::norm(quad[(i + 1) % 4] - quad[i]);
  spec->resize(4 * std::max(kMinProfiles, search.max_samples));
  (*first)[0] = 0;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = quad[i], q = quad[(i + 1) % 4];
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
    const double cell_p = cell_at(quad[(i + 3) % 4], p);
    const double cell_q = cell_at(quad[(i + 2) % 4], q);
    const int samples = std::max(
        kMinProfiles, static_cast<int>(std::min<double>(length / 2.0, search.max_samples)));
    (*first)[i + 1] = (*first)[i] + samples;
    for (int j = 0; j < samples; ++j) {
      const double t =
          kSideProfilesStart + (kSideProfilesEnd - kSideProfilesStart) * j / (samples - 1);
      const double local_cell = cell_p + t * (cell_q - cell_p);
      (*spec)[(*first)[i] + j] = {p + t * (q - p), outward,
                                  std::clamp(0.5 * local_cell, 1.0, search.max_half),
                                  0.5 * local_cell};
    }
  }
}

// A line through each side's edge points (edges[first[i] .. first[i + 1])
// for side i), the corners where they meet, and RefineQuad's checks against
// the quad they were searched from.
bool QuadFromEdges(const std::vector<ProfileEdge>& edges, const std::array<int, 5>& first,
                   const SideSearch& search, SideFitBuffers* buffers, Quad* quad) {
  std::vector<cv::Point2d>& points = buffers->points;
  std::array<Line, 4> sides;
  for (int i = 0; i < 4; ++i) {
    points.clear();
    for (int j = first[i]; j < first[i + 1]; ++j) {
      if (edges[j].found) points.push_back(edges[j].edge);
    }
    if (points.size() < 4) return false;
    if (!FitLine(&points, &buffers->residual, &buffers->sorted, &sides[i])) return false;
    if (buffers->side_fits) (*buffers->side_fits)[i] = SideFitOf(points, sides[i]);
  }
  Quad refined;
  if (!QuadFromSides(sides, &refined)) return false;
  for (int i = 0; i < 4; ++i) {
    // The refinement moves corners by the scans' error, about a pixel; a large
    // move means a side locked onto another edge.
    if (cv::norm(refined[i] - (*quad)[i]) > std::max(2.0, search.max_move_cells * search.cell)) {
      return false;
    }
  }
  if (!IsConvexClockwise(refined)) return false;
  *quad = refined;
  return true;
}

}  // namespace

bool RefineQuad(const ImageView& image, const SideSearch& search, SideFitBuffers* buffers,
                Quad* quad) {
  std::vector<ProfileSpec>& spec = buffers->spec;
  std::vector<ProfileEdge>& edges = buffers->edges;
  std::array<int, 5> first{};
  // The four sides' profiles are read in one batch (EdgePoints fills its
  // lanes across sides), then a line is fitted per side.
  SideProfiles(*quad, search, &spec, &first);
  edges.resize(spec.size());
  EdgePoints(image, search.channel, search.polarity, spec.data(), first[4], search.min_contrast,
             edges.data(), search.halfway);
  return QuadFromEdges(edges, first, search, buffers, quad);
}

namespace {

// One cell: the width of the black ring, between the outer and green quads.
double CellWidth(const Candidate& candidate) {
  return 0.5 * (QuadSide(candidate.quads[kBlackWhite]) - QuadSide(candidate.quads[kGreenBlack]));
}

}  // namespace

double ResolvedShare(double ring_share, double cell, double spread) {
  if (!(spread > 0.0)) return ring_share;
  const double resolved = std::clamp(
      (cell / spread - kUnresolvedRingCells) / (kResolvedRingCells - kUnresolvedRingCells), 0.0,
      1.0);
  return resolved * ring_share + (1.0 - resolved);
}

bool RefineOuterQuad(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate) {
  const double cell = CellWidth(*candidate);
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
    if (!RefineQuad(image, {kGray, kRisesOutwards, kMinGrayContrast, cell, 20, max_half}, buffers,
                    &candidate->quads[kBlackWhite]))
      return false;
    double moved = 0;
    for (int i = 0; i < 4; ++i)
      moved = std::max(moved, cv::norm(candidate->quads[kBlackWhite][i] - before[i]));
    if (moved < kSettledPx) break;
  }
  return true;
}

namespace {

// The share between the black ring's encoded-average [0] and linear-light
// [1] borders at which its inner square's side is `ratio` of its outer one's
// (sides, the square roots of the areas, are linear in the share), as far
// as the ring is resolved (ResolvedShare).
double RingShare(const Quad outer[2], const Quad inner[2], double ratio, double cell,
                 double spread) {
  double outer_side[2], inner_side[2];
  for (int way = 0; way < 2; ++way) {
    outer_side[way] = QuadSide(outer[way]);
    inner_side[way] = QuadSide(inner[way]);
  }
  const double change = (inner_side[1] - inner_side[0]) - ratio * (outer_side[1] - outer_side[0]);
  double share = 0.0;
  if (std::abs(change) > 1e-6)
    share = std::clamp((ratio * outer_side[0] - inner_side[0]) / change, 0.0, 1.0);
  return ResolvedShare(share, cell, spread);
}

}  // namespace

bool RefineReportedQuad(const ImageView& image, int cells, SideFitBuffers* buffers, Quad* quad,
                        cv::Matx<double, 8, 8>* covariance) {
  const double cell = QuadSide(*quad) / cells;
  if (!(cell > 1.0)) return false;
  // The black ring's outer (black/white) and inner (green/black) borders,
  // each with its edges at the encoded average [0] and in linear light [1].
  Quad outer[2] = {*quad, *quad};
  const Quad inner_start = InsetSquare(UnitSquareToQuad(*quad), 1.0 / cells);
  Quad inner[2] = {inner_start, inner_start};
  std::array<SideFit, 4> side_fits;
  bool inner_found = true;
  // The outer border at the encoded average is `quad` itself, as
  // RefineOuterQuad left it.
  for (int way = 0; way < 2; ++way) {
    const Halfway halfway = way == 0 ? Halfway::kEncoded : Halfway::kLinearLight;
    // Fewer profiles than the stages' searches: this runs on every detection,
    // and the lines average them. Up to 2.5 px either side of the encoded
    // average: a lens blur of 2 px puts the edge in linear light 1.3 px
    // outside it, beyond a search of 1.5 px.
    SideSearch out{kGray, kRisesOutwards, kMinGrayContrast, cell, kReportedOuterProfiles, 2.5};
    SideSearch in{kGray, kFallsOutwards, kMinGreenBlackContrast, cell, kMinProfiles, 2.5};
    out.halfway = in.halfway = halfway;
    // The linear-light outer sides' scatter stands for both conventions'
    // (the same profiles, read at another level).
    buffers->side_fits = way == 1 && covariance ? &side_fits : nullptr;
    const bool outer_found = way == 0 || RefineQuad(image, out, buffers, &outer[way]);
    buffers->side_fits = nullptr;
    if (!outer_found) return false;
    inner_found = inner_found && RefineQuad(image, in, buffers, &inner[way]);
  }
  // The ring's inner square is the outer one inset by a cell in the tag's
  // plane: under perspective its side is not (cells - 2) / cells of the
  // outer's (a near tag's far half is smaller; on the camera set's tags of
  // 150 px and more that proportion is off by up to 2 %, 0.2 px at the
  // corners).
  const double ratio = QuadSide(inner_start) / QuadSide(*quad);
  const double spread = 0.5 * (QuadSide(outer[1]) - QuadSide(outer[0]));
  // Without its inner border (a blur that leaves the ring no black), the
  // ring cannot tell: the share is a camera's.
  const double share = inner_found ? RingShare(outer, inner, ratio, cell, spread) : 1.0;
  for (int i = 0; i < 4; ++i) (*quad)[i] = outer[0][i] + share * (outer[1][i] - outer[0][i]);
  if (covariance) *covariance = ReportedCornerCovariance(side_fits, outer[0], outer[1]);
  return true;
}

bool RefineInnerQuads(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate) {
  const double cell = CellWidth(*candidate);
  if (!(cell > 1.0)) return false;
  return RefineQuad(image, {kGray, kFallsOutwards, kMinGreenBlackContrast, cell, 10, 2.5}, buffers,
                    &candidate->quads[kGreenBlack]) &&
         RefineQuad(image, {kRedMinusGreen, kFallsOutwards, kMinRedGreenContrast, cell, 10, 2.5},
                    buffers, &candidate->quads[kRedGreen]);
}

}  // namespace chromatag::internal
