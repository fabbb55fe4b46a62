// The second path: for a candidate whose red InitialScan found enclosed by
// green, but which the ring scans or a later stage then lost (thin or blurred
// rings, steep views, chroma smeared by JPEG or demosaicing), the black
// square is grown on L* from the centre (everything darker than the quiet
// zone), its outline cut to four sides and refined on the black/white edge,
// and the inner rings placed from each family's proportions and refined on
// their own edges. Then the same Decode. It runs only for such candidates.
#include "grow_region.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "decode.h"
#include "geometry.h"
#include "poly_to_quad.h"
#include "refine_corners.h"

namespace chromatag::internal {
namespace {

// The region is grown on a grid of about this many steps across the red's
// half-width: enough for an outline that the side fits then refine at full
// resolution, and a bounded cost on large tags.
constexpr float kGridStepsPerRedHalfWidth = 4.f;
// The window the black square may grow in: the scans' red/green border
// points pushed out from the centre by this factor (16h5's black square is 3
// times its red, 36h11's twice; then the quiet zone; and on small blurred
// tags the points fall up to halfway inside the red), plus a margin. A region
// that reaches the window's edge is not a tag's (it leaked).
constexpr float kWindowReach = 7.f;
constexpr int kWindowMarginPx = 4;
// The grown black square's area over the area inside the scans' red/green
// border points: 9 for 16h5 and 4 for 36h11 when the points are on the
// border. On small blurred tags the red's a* peaks in the middle and the
// points fall a pixel or two inside the true border, so the upper bound
// holds against the red widened by kBlurAllowancePx on each side.
constexpr double kMinAreaRatio = 2.5;
constexpr double kMaxAreaRatio = 16.0;
constexpr double kBlurAllowancePx = 2.0;
// Where the green is read past the scans' red/green border, as a fraction of
// the distance from the centre (inside the green ring for both families).
constexpr float kGreenProbe = 0.25f;
// The quiet zone starts within this many red/green border distances past the
// border (two for 16h5, one for 36h11; up to twice that where the points fell
// short of a small blurred red).
constexpr float kMaxQuietZoneReach = 4.f;
// The region darker than the quiet zone: below this fraction of the way from
// the lighter of the red and green to the quiet zone's white.
constexpr float kDarkFraction = 0.45f;
// The quiet zone must be at least this much lighter than the red and green,
// L* units.
constexpr float kMinWhiteGap = 8.f;
constexpr int kMinOutlinePoints = 8;
// Of the eight profiles out of the red, this many must read the green, and
// as many the quiet zone.
constexpr int kMinProfiles = 4;

struct Grid {
  int x0 = 0, y0 = 0;  // Image position of cell (0, 0).
  int step = 1;
  int width = 0, height = 0;
  cv::Point Pixel(int i, int j) const { return {x0 + i * step, y0 + j * step}; }
};

float Median(float* values, int n) {
  std::nth_element(values, values + n / 2, values + n);
  return values[n / 2];
}

// The lightness of the red and green (the lighter of the two) and of the
// quiet zone, from profiles outwards from the scans' red/green border
// points: past the border the profile darkens into the black ring, then
// lightens into the quiet zone.
bool RingLevels(const ImageView& image, const Candidate& candidate, float* chroma_l,
                float* white_l) {
  std::array<float, 8> green, white;
  int num_green = 0, num_white = 0;
  const cv::Point2f c = candidate.centre;
  const float red_l = image.L(RoundToInt(c.x), RoundToInt(c.y));
  for (const cv::Point2f& b : candidate.red_border) {
    const cv::Point2f probe = b + kGreenProbe * (b - c);
    if (!image.Contains(RoundToInt(probe.x), RoundToInt(probe.y))) continue;
    green[num_green++] = image.L(RoundToInt(probe.x), RoundToInt(probe.y));
  }
  if (num_green < kMinProfiles) return false;
  *chroma_l = std::max(red_l, Median(green.data(), num_green));
  const float dark = *chroma_l - std::max(6.f, 0.25f * *chroma_l);
  for (int i = 0; i < 8; ++i) {
    // Four of the eight profiles must find the quiet zone.
    if (num_white + (8 - i) < kMinProfiles) return false;
    const cv::Point2f& b = candidate.red_border[i];
    const cv::Point2f out = b - c;
    const float r = std::sqrt(out.dot(out));
    if (!(r > 0.5f)) continue;
    // Steps of an eighth of the red's half-width (the black ring is at least
    // half of it wide), until the quiet zone must have started.
    const float stride = std::max(1.f, r / kGridStepsPerRedHalfWidth / 2.f);
    const cv::Point2f u = stride * out / r;
    const int steps = static_cast<int>((kMaxQuietZoneReach * r + kWindowMarginPx) / stride);
    bool in_black = false;
    float lightest = -1.f;
    int light_until = 0;
    for (int k = 0; k <= steps || lightest >= 0.f; ++k) {
      const cv::Point2f p = b + static_cast<float>(k) * u;
      const int x = RoundToInt(p.x), y = RoundToInt(p.y);
      if (!image.Contains(x, y)) break;
      const float l = image.L(x, y);
      if (!in_black) {
        in_black = l < dark;
      } else if (lightest < 0.f && l > *chroma_l + kMinWhiteGap) {
        lightest = l;  // Entered the quiet zone: its lightest within half a red.
        light_until = k + static_cast<int>(0.5f * r / stride) + 2;
      } else if (lightest >= 0.f) {
        if (k > light_until) break;
        lightest = std::max(lightest, l);
      }
    }
    if (lightest >= 0.f) white[num_white++] = lightest;
  }
  if (num_white < kMinProfiles) return false;
  *white_l = Median(white.data(), num_white);
  return *white_l - *chroma_l >= kMinWhiteGap;
}

// Grows the region of grid cells for which `inside` holds, 4-connected, from
// `start`. Returns its outline (cells with a neighbour outside) in image
// pixels, or false if it reaches the window's edge or is too small.
template <typename Inside>
bool Grow(const Grid& grid, cv::Point start, int max_cells, Inside&& inside, RegionBuffers* buffers,
          std::vector<cv::Point2f>* outline) {
  std::vector<uint8_t>& state = buffers->state;  // 0 unseen, 1 in, 2 out, 3 queued.
  std::vector<int>& queue = buffers->queue;
  state.assign(static_cast<size_t>(grid.width) * grid.height, 0);
  queue.clear();
  auto test = [&](int i, int j) {
    uint8_t& s = state[static_cast<size_t>(j) * grid.width + i];
    if (s == 0) s = inside(grid.Pixel(i, j)) ? 1 : 2;
    return s != 2;
  };
  if (start.x < 0 || start.y < 0 || start.x >= grid.width || start.y >= grid.height ||
      !test(start.x, start.y))
    return false;
  queue.push_back(start.y * grid.width + start.x);
  state[queue.back()] = 3;
  outline->clear();
  for (size_t head = 0; head < queue.size(); ++head) {
    const int i = queue[head] % grid.width, j = queue[head] / grid.width;
    if (i == 0 || j == 0 || i == grid.width - 1 || j == grid.height - 1) return false;
    if (static_cast<int>(head) >= max_cells) return false;
    bool edge = false;
    const int neighbours[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
    for (const auto& n : neighbours) {
      const size_t index = static_cast<size_t>(n[1]) * grid.width + n[0];
      if (state[index] == 3) continue;
      if (test(n[0], n[1])) {
        state[index] = 3;
        queue.push_back(static_cast<int>(index));
      } else {
        edge = true;
      }
    }
    if (edge) outline->push_back(cv::Point2f(grid.Pixel(i, j)));
  }
  return static_cast<int>(outline->size()) >= kMinOutlinePoints;
}

// Keeps only the leftmost and rightmost of the outline's cells on each grid
// row, in row order. Their convex hull is the whole outline's (a hull vertex
// is extreme in its row), and FitQuad then sorts a few dozen points instead
// of every cell on the outline: the same quad.
void RowEnds(const Grid& grid, RegionBuffers* buffers, std::vector<cv::Point2f>* outline) {
  std::vector<std::array<float, 2>>& ends = buffers->row_ends;  // Per row: least x, greatest x.
  ends.assign(grid.height, {1e30f, -1e30f});
  for (const cv::Point2f& p : *outline) {
    auto& row = ends[(static_cast<int>(p.y) - grid.y0) / grid.step];
    row[0] = std::min(row[0], p.x);
    row[1] = std::max(row[1], p.x);
  }
  outline->clear();
  for (int j = 0; j < grid.height; ++j) {
    if (ends[j][0] > ends[j][1]) continue;
    const float y = static_cast<float>(grid.y0 + j * grid.step);
    outline->push_back({ends[j][0], y});
    if (ends[j][1] > ends[j][0]) outline->push_back({ends[j][1], y});
  }
}

// Whether, along each ray from the centre through a red/green border point,
// the image turns at least as light as L* `threshold` (given as
// ColorTable::YForL of it) within `reach` times the border point's distance
// (widened by `allowance` px): the black square ends there.
bool BoundedAlongRays(const ImageView& image, const Candidate& candidate, int32_t threshold_y,
                      int stride, double reach, double allowance) {
  const cv::Point2f c = candidate.centre;
  for (const cv::Point2f& b : candidate.red_border) {
    const cv::Point2f out = b - c;
    const float r = std::sqrt(out.dot(out));
    if (!(r > 0.5f)) continue;
    const cv::Point2f u = static_cast<float>(stride) * out / r;
    const int steps = static_cast<int>(reach * (r + allowance) / stride) + 1;
    bool ended = false;
    for (int k = 1; k <= steps && !ended; ++k) {
      const cv::Point2f p = c + static_cast<float>(k) * u;
      const int x = RoundToInt(p.x), y = RoundToInt(p.y);
      if (!image.Contains(x, y)) return false;
      ended = image.Y(x, y) >= threshold_y;
    }
    if (!ended) return false;
  }
  return true;
}

// Places the green/black and red/green borders of a tag of `family` inside
// the outer quad, from the family's proportions, and fits each on its edge.
bool PlaceInnerRings(const ImageView& image, const TagFamily& family, SideFitBuffers* buffers,
                     Candidate* candidate) {
  const double cells = family.black_square_cells();
  const cv::Matx33d from_outer = UnitSquareToQuad(candidate->quads[kBlackWhite]);
  const double cell = std::sqrt(QuadArea(candidate->quads[kBlackWhite])) / cells;
  const double half = std::max(1.5, 0.35 * cell);
  Quad green = InsetSquare(from_outer, 1 / cells);
  Quad red = InsetSquare(from_outer, 2 / cells);
  if (!RefineQuad(image, {kGray, kFallsOutwards, kMinGreenBlackContrast, cell, 10, half}, buffers,
                  &green) ||
      !RefineQuad(image, {kRedMinusGreen, kFallsOutwards, kMinRedGreenContrast, cell, 10, half},
                  buffers, &red))
    return false;
  candidate->quads[kGreenBlack] = green;
  candidate->quads[kRedGreen] = red;
  return true;
}

}  // namespace

bool WorthGrowing(const Candidate& candidate, RejectReason why) {
  // Red things that are not tags mostly fail re-centring (a red blob next to
  // some green); a tag the scans lose gets as far as the ring scans. On
  // tag-free camera frames that leaves one candidate in five, and no tag the
  // second path found had failed earlier.
  return candidate.enclosed && why >= RejectReason::kRingScan;
}

namespace {

// The grid GrowRegion grows on: the window around the scans' red/green
// border points pushed outwards (kWindowReach), inside the frame, with
// kGridStepsPerRedHalfWidth steps across the red's half-width. False when
// it is too small to grow in.
bool WindowAround(const ImageView& image, const Candidate& candidate, Grid* grid) {
  const cv::Point2f c = candidate.centre;
  float min_x = 1e30f, min_y = 1e30f, max_x = -1e30f, max_y = -1e30f, half_width = 0.f;
  for (const cv::Point2f& b : candidate.red_border) {
    const cv::Point2f p = c + kWindowReach * (b - c);
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    half_width += 0.125f * static_cast<float>(cv::norm(b - c));
  }
  grid->step = std::max(1, static_cast<int>(half_width / kGridStepsPerRedHalfWidth));
  // Bounded to the frame as floats before the casts.
  auto inside = [](float v, int size) {
    return static_cast<int>(std::clamp(v, -1.f, static_cast<float>(size)));
  };
  grid->x0 = std::max(0, inside(min_x, image.width()) - kWindowMarginPx);
  grid->y0 = std::max(0, inside(min_y, image.height()) - kWindowMarginPx);
  const int x1 = std::min(image.width() - 1, inside(max_x, image.width()) + kWindowMarginPx);
  const int y1 = std::min(image.height() - 1, inside(max_y, image.height()) + kWindowMarginPx);
  grid->width = (x1 - grid->x0) / grid->step + 1;
  grid->height = (y1 - grid->y0) / grid->step + 1;
  return grid->width >= 3 && grid->height >= 3;
}

// The black square's outline: everything darker than its quiet zone (the
// red, the green and the black ring alike, whatever the light), grown on
// the grid from the centre; no larger than `max_area` (px^2) around the
// red, past which the region has leaked. False when it leaks or is open.
bool GrowBlackSquare(const ImageView& image, const Candidate& candidate, const Grid& grid,
                     float chroma_l, float white_l, double max_area, RegionBuffers* buffers,
                     std::vector<cv::Point2f>* outline) {
  const cv::Point2f c = candidate.centre;
  const float threshold = chroma_l + kDarkFraction * (white_l - chroma_l);
  // L* < threshold, tested as Y < threshold_y (the same answer for every
  // colour): the fill below tests up to a thousand cells.
  const int32_t threshold_y = image.table().YForL(threshold);
  const cv::Point start(RoundToInt((c.x - grid.x0) / grid.step),
                        RoundToInt((c.y - grid.y0) / grid.step));
  const int max_cells = static_cast<int>(max_area / (grid.step * grid.step)) + 16;
  // The same bound along each scan direction first, which costs a few dozen
  // pixels instead of the thousands a leaking region fills before it is
  // caught: most candidates that get here and are not tags leak.
  return BoundedAlongRays(image, candidate, threshold_y, grid.step, std::sqrt(kMaxAreaRatio),
                          kBlurAllowancePx) &&
         Grow(
             grid, start, max_cells, [&](cv::Point p) { return image.Y(p.x, p.y) < threshold_y; },
             buffers, outline);
}

// The black square's quad from its outline: four sides, an area between
// kMinAreaRatio times the red's (`red_area`) and `max_area`, then moved onto
// its black/white edge. False when it is no such quad.
bool OuterQuadOf(const ImageView& image, const Grid& grid, double red_area, double max_area,
                 RegionBuffers* region_buffers, QuadFitBuffers* fit_buffers,
                 SideFitBuffers* side_buffers, std::vector<cv::Point2f>* outline, Quad* outer) {
  RowEnds(grid, region_buffers, outline);
  if (!FitQuad(*outline, fit_buffers, outer)) return false;
  if (QuadArea(*outer) < kMinAreaRatio * red_area || QuadArea(*outer) > max_area) return false;
  const double cell = std::sqrt(QuadArea(*outer)) / 8.0;  // Either family: refined next.
  return RefineQuad(image,
                    {kGray, kRisesOutwards, kMinGrayContrast, cell, 20, grid.step + 1.5, 1.0},
                    side_buffers, outer) &&
         RefineQuad(image, {kGray, kRisesOutwards, kMinGrayContrast, cell, 20, 1.5}, side_buffers,
                    outer);
}

}  // namespace

bool GrowRegion(const ImageView& image, const DetectorOptions& options,
                const std::vector<FamilyDecoder>& families, RegionBuffers* region_buffers,
                QuadFitBuffers* fit_buffers, SideFitBuffers* side_buffers, Candidate* candidate,
                Detection* detection, RejectReason* why) {
  *why = RejectReason::kNoQuietZone;
  if (!candidate->enclosed) return false;
  float chroma_l = 0.f, white_l = 0.f;
  if (!RingLevels(image, *candidate, &chroma_l, &white_l)) return false;
  Grid grid;
  if (!WindowAround(image, *candidate, &grid)) return false;

  *why = RejectReason::kSquareOpen;
  std::vector<cv::Point2f>& outline = candidate->points[kBlackWhite];
  // A region larger than any tag's black square around this red has leaked.
  const double red_area = PolygonArea({candidate->red_border.begin(), candidate->red_border.end()});
  const double widened = std::pow(std::sqrt(red_area) + 2 * kBlurAllowancePx, 2);
  if (!GrowBlackSquare(image, *candidate, grid, chroma_l, white_l, kMaxAreaRatio * widened,
                       region_buffers, &outline))
    return false;

  *why = RejectReason::kSquareNotQuad;
  Quad outer;
  if (!OuterQuadOf(image, grid, red_area, kMaxAreaRatio * widened, region_buffers, fit_buffers,
                   side_buffers, &outline, &outer))
    return false;
  candidate->quads[kBlackWhite] = outer;

  *why = RejectReason::kNoInnerRings;
  for (const FamilyDecoder& entry : families) {
    if (!PlaceInnerRings(image, *entry.family, side_buffers, candidate)) continue;
    // Decode tells the families apart by the rings' proportions, which now
    // follow this family's.
    if (Decode(image, options, families, *candidate, side_buffers, detection, why,
               &candidate->fits_swapped_print))
      return true;
  }
  return false;
}

}  // namespace chromatag::internal
