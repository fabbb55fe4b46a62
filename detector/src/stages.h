// The stages of Algorithm 1 (paper section 4), one file and one function
// each, and the candidate they build up. Internal to the detector.
#ifndef CHROMATAG_DETECTOR_SRC_STAGES_H_
#define CHROMATAG_DETECTOR_SRC_STAGES_H_

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "chromatag/families/decoder.h"
#include "chromatag/families/family.h"
#include "image_view.h"

namespace chromatag::internal {

// The three borders a scan from the tag centre crosses, inside out.
enum Ring { kRedGreen = 0, kGreenBlack = 1, kBlackWhite = 2 };
inline constexpr int kNumRings = 3;

using Quad = std::array<cv::Point2d, 4>;  // Clockwise on screen (x right, y down).

// Where one scan from the centre crossed each border (sub-pixel).
struct RingHits {
  std::array<cv::Point2f, kNumRings> border;
};

// Scratch memory. A stage that needs buffers takes them from its caller, one
// struct per kind of work, so that its signature says what it writes besides
// its results; the detector keeps one of each in its Scratch (below), reused
// from call to call, so that a warm Detect allocates nothing. The buffers
// carry nothing from one call to the next that a call reads.
//
// FindADiff: a sampled row's a* (or coarse a*) and the samples that may rise.
// The cursor points into `rises` until the row is done.
struct RowScanBuffers {
  std::vector<int32_t> a;
  std::vector<int> rises;
};
// ScanRings: the values read along a scan, one per step.
struct RingScanBuffers {
  std::vector<float> values;
};
// BuildPolygon: the outer polygon's hull, and the points sorted for it
// (ClockwiseHull).
struct PolygonBuffers {
  std::vector<cv::Point2f> sorted, hull;
};
// FitQuad: the points' hull (and the points sorted for it), the vertices
// still kept as the hull is cut to four corners, and each hull edge's side.
struct QuadFitBuffers {
  std::vector<cv::Point2f> sorted, hull;
  std::vector<int> prev, next;
  std::vector<double> area;
  std::vector<int> label;
};
// GrowRegion's fill: each grid cell's state, the cells queued, and the
// outline's ends on each grid row.
struct RegionBuffers {
  std::vector<uint8_t> state;
  std::vector<int> queue;
  std::vector<std::array<float, 2>> row_ends;
};
// RefineQuad and the stages that call it (defined with it below).
struct SideFitBuffers;

// A tag candidate as the stages build it.
struct Candidate {
  cv::Point2f centre;       // Converged centre of the red region (InitialScan).
  float reference_red = 0;  // ReferenceRed, a*.
  // Border points per ring, from every scan (InitialScan and BuildPolygon).
  std::array<std::vector<cv::Point2f>, kNumRings> points;
  std::vector<cv::Point2f> scan_directions;  // Unit directions already scanned.
  std::array<Quad, kNumRings> quads;
  // The red/green border points of InitialScan's last completed centring
  // pass, in eight directions from `centre`: a red region enclosed by
  // far less red. `enclosed` is false until a pass completed.
  bool enclosed = false;
  std::array<cv::Point2f, 8> red_border;
};

// The eight directions InitialScan and QuadsFromScans scan in from a
// candidate's centre, clockwise on screen from "right": the axes (right,
// down, left, up; the paper's four scans) at even indices, the diagonals
// between them. Unit steps, so that every scan samples a ring as densely (M
// pixels must fit in a ring whatever the direction).
inline constexpr float kDiagonalStep = 0.70710678f;
inline const cv::Point2f kScanDirections[8] = {
    {1, 0},  {kDiagonalStep, kDiagonalStep},   {0, 1},  {-kDiagonalStep, kDiagonalStep},
    {-1, 0}, {-kDiagonalStep, -kDiagonalStep}, {0, -1}, {kDiagonalStep, -kDiagonalStep}};

// An accepted detection's area, which FindADiff skips.
struct DetectedArea {
  Quad quad;  // The outer quad grown by one cell (the quiet zone).
  double min_y = 0, max_y = 0;
  // The range [x_begin, x_end] the area covers on row y; false if none.
  bool RowSpan(double y, double* x_begin, double* x_end) const;
};

// FindADiff's position on its current sampled row. On the first call the
// whole row is sampled at once (SIMD where available) and the rises the
// prefilter lets through are listed (ScanRow); later calls walk that list.
struct RowCursor {
  int y = 0;
  // The row's place among the frame's `num_rows` sampled rows and the next
  // one's y (-1 after the last), for FindADiff's prefetches; SampledRow sets
  // them (a cursor without them prefetches nothing).
  int row = 0;
  int num_rows = 0;
  int next_y = -1;
  bool sampled = false;
  const int* rises = nullptr;  // Sample indices i that may rise from i - 1.
  int num_rises = 0;
  int next = 0;  // Next entry of `rises` to look at.
};

// The frame's sampled rows, y = 0, r, 2 r, ... below `height` (r =
// DetectorOptions::sampled_row_step): their number, and a cursor at the
// start of row number `row` of them. The one row schedule: Detect walks it,
// and FindADiff prefetches by it.
inline int NumSampledRows(int height, const DetectorOptions& options) {
  const int row_step = options.sampled_row_step();
  return (height + row_step - 1) / row_step;
}
inline RowCursor SampledRow(int height, const DetectorOptions& options, int row) {
  RowCursor cursor;
  cursor.row = row;
  cursor.num_rows = NumSampledRows(height, options);
  cursor.y = row * options.sampled_row_step();
  cursor.next_y = row + 1 < cursor.num_rows ? cursor.y + options.sampled_row_step() : -1;
  return cursor;
}

// How FindADiff's row scan finds the samples that may rise, by the kernels'
// path (kernels/kernels.h). Each is a conservative prefilter of the accurate
// rise (none is ever missed); they differ in speed and in how many false
// rises they let through:
// - with AVX-512 (VBMI) and N = 4: a* computed in 16-bit lanes
//   (ColorTable::FastA, within kFastAErrorBound), 32 samples at a time;
// - otherwise the coarse a* table, eight samples at a time with AVX2, else
//   one at a time.

// The rise in ColorTable::FastA units that the computed a* lets through: a
// true rise above `adiff_thresh` shows at least this much, as each of the two
// samples' FastA is within kFastAErrorBound of its accurate a*.
int ComputedARiseThreshold(double adiff_thresh);
// The FastA below which the computed a* takes a sample two back as green
// (SeedsAt): every sample whose accurate a* is below kTwoStepGreenA.
int ComputedAGreenLimit();
// The FastA above which it takes a sample as red enough to end such a rise:
// every sample whose accurate a* is at least kTwoStepMinRedA.
int ComputedATwoStepRedFloor();

// Whether FindADiff computes a* with these options and the view's kernels.
// Then its row scan does not read the coarse a* table, and FindADiff brings
// the table in for the later stages a few lines per sampled row
// (ColorTable::PrefetchCoarseLines) instead of Detect streaming it first.
bool RowScanComputesA(const ImageView& image, const DetectorOptions& options);

// FindADiff's second kind of rise (DetectorOptions::two_step_rises; not in
// the paper): sample i seeds when
// its a* rises by more than ADiffThresh over sample i - 2, that sample is
// green (a* below kTwoStepGreenA), and both steps rise by more than
// kTwoStepShare of ADiffThresh. A tag's red/green border blurred by the
// optics, demosaicing or JPEG's 4:2:0 chroma spreads over 8 px or more, and
// on a dim card or a washed-out print its step then falls into two samples
// each under ADiffThresh: an iccv17 print at 0.37 of the light under a
// tungsten cast reads a* -9, 12, 29 on three samples across a 135 px tag's
// border, and no sample seeded. Rises over two samples from grey or red
// (most of a natural scene's) do not count, nor does the sample after a
// one-step rise (its second step is flat), nor a sample short of
// kTwoStepMinRedA or darker than kTwoStepMinL: the rises of this kind in
// natural scenes mostly end weakly red or in the dark, where a* is noise.
// On 804 camera-set frames, outside the cards: 40.3 one-step rises a frame,
// 6.4 more of this kind; they seed 43 of the 45 tags of 30 px or more
// (up to 60 degrees) that no one-step rise seeded.
inline constexpr float kTwoStepGreenA = -4.f;
inline constexpr float kTwoStepShare = 0.25f;
inline constexpr float kTwoStepMinRedA = 18.f;
inline constexpr float kTwoStepMinL = 15.f;

// Whether a sample (a*, L*) seeds after a* `before` and `two_before` (the
// accurate test FindADiff applies; `two_before` NaN where there is none).
inline bool SeedsAt(const DetectorOptions& options, LabF lab, float before, float two_before) {
  const float thresh = static_cast<float>(options.adiff_thresh);
  const float a = lab.a;
  if (a - before > thresh) return true;
  if (!options.two_step_rises) return false;
  const float step = kTwoStepShare * thresh;
  return two_before < kTwoStepGreenA && a - two_before > thresh && a - before > step &&
         before - two_before > step && a >= kTwoStepMinRedA && lab.L >= kTwoStepMinL;
}

// FindADiff's scan of sampled row y: fills `rises` (one entry per sample at
// most) with the indices i (x = i N) that may seed (SeedsAt: a* rising from
// sample i - 1 by more than ADiffThresh, or, with two_step_rises, from a
// green sample i - 2 in two steps), in order, and returns their number. `coarse` is
// scratch of one entry per sample.
int ScanRow(const ImageView& image, const DetectorOptions& options, int y, int32_t* coarse,
            int* rises);

// A family the detector looks for, with its decoder.
struct FamilyDecoder {
  std::shared_ptr<const TagFamily> family;
  std::unique_ptr<CodeDecoder> decoder;
  // What a tag printed with its shades swapped shows: within each colour,
  // the complement of each kept code in each of its four orientations
  // (SwappedCodes; Decode compares close-code reads with them).
  std::vector<Code> swapped_codes;
};

// The swapped prints' codes of `family` (FamilyDecoder::swapped_codes).
std::vector<Code> SwappedCodes(const TagFamily& family);

// Stages 2-5 return false and set *why when they abandon a candidate.

// 1. FindADiff: advances along the cursor's row, sampling every N-th pixel,
// to the next sample whose a* rises by more than ADiffThresh over the previous
// sample of the row, skipping accepted areas. False at the row's end.
// *prefilter_rejects counts rises the row scan's prefilter suggested but the
// accurate a* refuted.
bool FindADiff(const ImageView& image, const DetectorOptions& options,
               const std::vector<DetectedArea>& skip, RowScanBuffers* buffers, RowCursor* cursor,
               cv::Point* seed, int* prefilter_rejects);

// The a* drop from ReferenceRed that counts a pixel as past the red/green
// border: BorderThresh, or a third of the red's a* if more. The two reds share
// one a* in the palettes, but a colour cast or JPEG's chroma blur part them by
// 10 units or more, and BorderThresh alone then stops scans inside the red.
// Green's a* is negative, so the drop across the border always exceeds the
// red's a*.
inline float RedGreenThresh(const DetectorOptions& options, float reference_red) {
  return std::max(static_cast<float>(options.border_thresh), reference_red / 3.f);
}

// One scan outwards from `start` along the unit vector `direction`, one pixel
// (nearest) per unit step, through the three borders. ReferenceRed
// is carried in; ReferenceGreen and ReferenceBlack are picked up on the way.
// False if a border is not found within reach of the previous one or the scan
// leaves the frame.
bool ScanRings(const ImageView& image, const DetectorOptions& options, cv::Point2f start,
               cv::Point2f direction, float reference_red, RingScanBuffers* buffers,
               RingHits* hits);

// The red/green border polygon of a red region InitialScan rejected after at
// least one centring pass (eight points, star-shaped around its centre).
struct RejectedRegion {
  std::array<cv::Point2f, 8> border;
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  // Every seed is tested against every region rejected so far in the frame
  // (hundreds on busy frames): the box test inline, the polygon only inside.
  bool Contains(cv::Point2f p) const {
    return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y && BorderContains(p);
  }
  bool BorderContains(cv::Point2f p) const;  // Even-odd rule over `border`.
  // The region of a centring pass's red/green border points, grown a little
  // about its centre: the seeds of later rows lie on the region's left edge,
  // where the polygon's sides cut inside.
  static RejectedRegion Around(const std::array<cv::Point2f, 8>& red_border);
};

// 2. InitialScan: scans left, right, up and down from the seed to the
// red/green border, re-centres until the centre converges, then scans on
// through all three borders. Seeds the candidate's polygons. With `rejected`
// (the frame's regions rejected so far), a seed inside one of them is dropped
// at once, and a region rejected after a centring pass is added.
bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed,
                 RingScanBuffers* buffers, Candidate* candidate,
                 std::vector<RejectedRegion>* rejected, RejectReason* why);

// 3. BuildPolygon: greedy scans towards the largest convexity-limited
// potential area of the outer polygon until area / (area + potential) exceeds
// ConvThresh. Every scan adds a point to each of the three polygons.
bool BuildPolygon(const ImageView& image, const DetectorOptions& options,
                  RingScanBuffers* scan_buffers, PolygonBuffers* buffers, Candidate* candidate,
                  RejectReason* why);

// 4. PolyToQuad: a quad per polygon (FitQuad: the hull cut to four corners,
// a line per side, their intersections); then NestedAndRefined.
bool PolyToQuad(const ImageView& image, bool refine_sides, QuadFitBuffers* fit_buffers,
                SideFitBuffers* side_buffers, Candidate* candidate, RejectReason* why);

// PolyToQuad's second half: false (and *why) unless the three quads are
// nested, each inside the next; then, if `refine_sides`, RefineOuterQuad.
bool NestedAndRefined(const ImageView& image, bool refine_sides, SideFitBuffers* buffers,
                      Candidate* candidate, RejectReason* why);

// The fast path from InitialScan to the sub-pixel sides
// (quad_from_scans.cc): the four diagonal scans through the rings added to
// InitialScan's four axis ones, and each ring's quad from its eight border
// points, split into four runs of consecutive points, one per side, whose
// edge directions run across their sides. False when no split gives a quad
// for every ring; the candidate's points and scan
// directions are left as they were (only its quads are written), so that
// BuildPolygon can take over.
bool QuadsFromScans(const ImageView& image, const DetectorOptions& options,
                    RingScanBuffers* buffers, Candidate* candidate);

// The second path (grow_region.cc). WorthGrowing: whether a candidate the
// stages above lost (for `why`) is one the second path can rescue: its red
// was enclosed by green and it got as far as the ring scans. GrowRegion:
// grows the black square from the centre (everything darker than the quiet
// zone, levels from the candidate's own profiles), fits its four sides and
// refines them, places each family's green and red rings inside it and fits
// them on their edges, then Decode. Overwrites the candidate's quads and
// outer points.
bool WorthGrowing(const Candidate& candidate, RejectReason why);
bool GrowRegion(const ImageView& image, const DetectorOptions& options,
                const std::vector<FamilyDecoder>& families, RegionBuffers* region_buffers,
                QuadFitBuffers* fit_buffers, SideFitBuffers* side_buffers, Candidate* candidate,
                Detection* detection, RejectReason* why);

// Sub-pixel sides (refine_corners.cc): least-squares lines through edge
// points found along each side, corners where they meet. RefineOuterQuad
// moves the black/white quad (the reported corners and the homography);
// RefineInnerQuads the green/black and red/green ones, which only Decode's
// ring proportions read (DecodeCandidate refines them when the rough ones
// fit no family). False if a side has too few edge points to fit, a corner
// jumps or the quad turns concave; the ring's cell must exceed a pixel.
bool RefineOuterQuad(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate);
// The reported corners of a decoded tag whose black square has `cells`
// cells: `quad` (its black/white quad as the stages found it, edges at the
// encoded average) moved towards where its edges lie in linear light, as
// far as the black ring says. Where an image was blurred decides where its
// edges lie between their levels: a lens blurs light (linear light is
// right), software that resizes or warps an sRGB image blurs its encoded
// values (the encoded average is right). The black ring is one cell wide:
// its outer and inner borders, each located both ways, are mixed in the
// share that gives it that width, and the outer corners in the same share.
// False (quad untouched) when a border cannot be located.
bool RefineReportedQuad(const ImageView& image, int cells, SideFitBuffers* buffers, Quad* quad);
bool RefineInnerQuads(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate);

// Four sides from the convex hull of `points` (the hull cut to its four
// corners by dropping the vertex of the smallest triangle, a line fitted
// through each side's hull edges) and their corners, clockwise. False if
// they do not make a convex quad.
bool FitQuad(const std::vector<cv::Point2f>& points, QuadFitBuffers* buffers, Quad* quad);

// Contrast floors for side searches in encoded 8-bit units (gray is the sum
// of three channels).
inline constexpr float kMinGrayContrast = 30.f;
// Green against black is a smaller step than black against white: a dim
// green under a cast and a steep tone curve is 15-40 above the black.
inline constexpr float kMinGreenBlackContrast = 12.f;
inline constexpr float kMinRedGreenContrast = 20.f;
// Across each ring's border, outwards: black to white rises in gray, green
// to black falls, red to green falls in R - G.
inline constexpr int kRisesOutwards = 1;
inline constexpr int kFallsOutwards = -1;

// Where an edge is taken to lie between its two levels: halfway in the
// encoded values, or halfway in linear light (the gray channel decoded with
// sRGB's curve; other channels keep the encoded average). A lens blurs light,
// so in a camera's frames an edge is halfway in linear light, which in
// encoded values lies nearer the dark level: the encoded average finds a
// black square too small, by about 0.8 px on the camera set. The detector's
// stages were tuned on the encoded average (ring proportions); the reported
// corners lie between the two, where the black ring's width puts them
// (RefineReportedQuad).
enum class Halfway { kEncoded, kLinearLight };

// How RefineQuad looks for one ring's sides.
struct SideSearch {
  ChannelWeights channel;  // kGray for the black ring's borders, kRedMinusGreen for red/green.
  // Whether the channel rises (kRisesOutwards) or falls (kFallsOutwards)
  // outwards across the edge; steps the other way round are not taken.
  int polarity = kRisesOutwards;
  float min_contrast = kMinGrayContrast;  // Smallest step between the two levels.
  double cell = 0;        // Cell size in pixels: the levels are read half a cell either side.
  int max_samples = 10;   // Profiles per side (at most; about one per 2 px).
  double max_half = 2.5;  // Search either side of the current line, pixels.
  double max_move_cells = 0.75;  // A corner moving farther (and over 2 px) fails the fit.
  // Where the edge lies between the two levels (EdgePoint): their average,
  // or halfway in linear light (Halfway).
  Halfway halfway = Halfway::kEncoded;
};

// One profile across a side (refine_corners.cc): centred on `middle`,
// searched `half` pixels either way along `outward` (the side's outward unit
// normal), the two levels read `level_offset` either side of the steepest
// change.
// A profile's samples lie kProfileStep pixels apart, at most
// kMaxProfileSteps either side of its middle (4 px).
inline constexpr float kProfileStep = 0.5f;
inline constexpr int kMaxProfileSteps = 8;
struct ProfileSpec {
  cv::Point2d middle;
  cv::Point2d outward;
  double half = 0;
  double level_offset = 0;
};
struct ProfileEdge {
  cv::Point2d edge;
  bool found = false;
};

// RefineQuad's buffers: the profiles across the four sides and their edge
// points, one side's points found, and its line's residuals (FitLine).
struct SideFitBuffers {
  std::vector<ProfileSpec> spec;
  std::vector<ProfileEdge> edges;
  std::vector<cv::Point2d> points;
  std::vector<double> residual, sorted;
};
// The edge point on one profile: where `channel` passes halfway between the
// two levels (in linear light for the gray channel with Halfway::kLinearLight:
// profile and levels decoded first), nearest the steepest change the
// `polarity` way round. False
// if the profile leaves the frame, has no such change, or the levels differ
// by less than `min_contrast`.
bool EdgePoint(const ImageView& image, const ChannelWeights& channel, int polarity,
               const ProfileSpec& spec, float min_contrast, cv::Point2d* edge,
               Halfway halfway = Halfway::kEncoded);
// EdgePoint for each of `count` profiles, into out[0 .. count); eight at a
// time by the view's vector kernel where it has one, with the same results.
void EdgePoints(const ImageView& image, const ChannelWeights& channel, int polarity,
                const ProfileSpec* spec, int count, float min_contrast, ProfileEdge* out,
                Halfway halfway = Halfway::kEncoded);

// Moves the sides of `quad` onto the edge of `search.channel` nearest to
// them: sub-pixel edge points on short profiles across each side, a robust
// line per side, corners where they meet. False (quad untouched) if a side
// has too few edge points, a corner jumps or the result is not convex.
bool RefineQuad(const ImageView& image, const SideSearch& search, SideFitBuffers* buffers,
                Quad* quad);

// Decode reads each cell as the mean colour of a samples x samples grid of
// pixels: the ones nearest to centre + s du + t dv, s and t evenly from -1 to
// 1 (samples from 2 to 8). SumCellGrid sums their R, G and B and counts them,
// points outside the frame skipped; eight points at a time by the view's
// vector kernel where it has one, with the same sums.
struct PixelSums {
  int r = 0, g = 0, b = 0, n = 0;
};
PixelSums SumCellGrid(const ImageView& image, cv::Point2d centre, cv::Point2d du, cv::Point2d dv,
                      int samples);

// 5. Decode: picks the family whose ring proportions match, reads every
// payload cell in b*, splits each colour at its own midpoint, looks the code
// up over all rotations and fills the detection in the decoded orientation.
bool Decode(const ImageView& image, const DetectorOptions& options,
            const std::vector<FamilyDecoder>& families, const Candidate& candidate,
            SideFitBuffers* buffers, Detection* detection, RejectReason* why);

// Decode for a candidate whose inner quads are still rough (from the scans or
// the polygons; only the outer one has its sub-pixel sides): where they fit
// no family's proportions, RefineInnerQuads (if `refine_sides`) and Decode
// once more. The first reason stands if that fails too.
bool DecodeCandidate(const ImageView& image, const DetectorOptions& options, bool refine_sides,
                     const std::vector<FamilyDecoder>& families, SideFitBuffers* buffers,
                     Candidate* candidate, Detection* detection, RejectReason* why);

// Geometry helpers (geometry.cc), unsigned areas in square pixels.
double PolygonArea(const std::vector<cv::Point2f>& polygon);
double QuadArea(const Quad& quad);
// Area centroid of a simple polygon; NaN if degenerate.
cv::Point2f PolygonCentroid(const cv::Point2f* polygon, size_t n);
template <size_t N>
cv::Point2f PolygonCentroid(const std::array<cv::Point2f, N>& polygon) {
  return PolygonCentroid(polygon.data(), N);
}
// Where the lines p1 + s d1 and p2 + t d2 meet; false if they are parallel
// within 1e-12 of the directions' lengths. Inline: BuildPolygon calls it for
// every hull edge on every scan, and across a call the points' coordinates
// went through memory (stalls that cost more than the arithmetic).
inline bool IntersectLines(cv::Point2d p1, cv::Point2d d1, cv::Point2d p2, cv::Point2d d2,
                           cv::Point2d* at) {
  const double det = d1.x * d2.y - d1.y * d2.x;
  // Parallel within 1e-12 of the directions' lengths. The L1 lengths bound
  // the L2 ones from above, so a determinant past their bound is past this
  // one too: the square roots are taken only near the limit (BuildPolygon
  // calls this for every hull edge on every scan).
  const double l1 = (std::abs(d1.x) + std::abs(d1.y)) * (std::abs(d2.x) + std::abs(d2.y));
  if (!(std::abs(det) >= 1e-12 * (l1 + 1e-300)) &&
      std::abs(det) < 1e-12 * (cv::norm(d1) * cv::norm(d2) + 1e-300)) {
    return false;
  }
  const cv::Point2d w = p2 - p1;
  const double s = (w.x * d2.y - w.y * d2.x) / det;
  *at = p1 + s * d1;
  return true;
}
bool IsConvexClockwise(const Quad& quad);
// A line through `point` along `direction` (unit where Distance is used).
struct Line {
  cv::Point2d point;
  cv::Point2d direction;
  double Distance(const cv::Point2d& p) const {
    const cv::Point2d d = p - point;
    return std::abs(d.x * direction.y - d.y * direction.x);
  }
};
// The quad whose side i is sides[i]: corner i where side i - 1 meets side i.
// False if two neighbouring sides are parallel.
inline bool QuadFromSides(const std::array<Line, 4>& sides, Quad* quad) {
  for (int i = 0; i < 4; ++i) {
    const Line& a = sides[(i + 3) % 4];
    const Line& b = sides[i];
    if (!IntersectLines(a.point, a.direction, b.point, b.direction, &(*quad)[i])) return false;
  }
  return true;
}
// The unit direction of the major axis of a scatter with second moments
// sxx, sxy, syy about its mean (the total least squares line's direction),
// x >= 0 (y > 0 when x = 0); in closed form, no trigonometry. (1, 0) for a
// scatter with no spread.
cv::Point2d MajorAxis(double sxx, double sxy, double syy);
// The convex hull of `points`, clockwise on screen (y down), without
// collinear points; into *hull (reused, with *sorted for the points sorted)
// or returned.
void ClockwiseHull(const std::vector<cv::Point2f>& points, std::vector<cv::Point2f>* sorted,
                   std::vector<cv::Point2f>* hull);
std::vector<cv::Point2f> ClockwiseHull(const std::vector<cv::Point2f>& points);
// The homography from the unit square ((0,0), (1,0), (1,1), (0,1)) to `quad`,
// and a point through a homography (inline, as IntersectLines: Decode maps
// three points a cell).
cv::Matx33d UnitSquareToQuad(const Quad& quad);
inline cv::Point2d ApplyHomography(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}
// The square from (inset, inset) to (1 - inset, 1 - inset) of the unit
// square through `h`, clockwise from its top-left: with `h` a tag's
// UnitSquareToQuad, the border `inset` * cells cells inside its black square.
inline Quad InsetSquare(const cv::Matx33d& h, double inset) {
  const double lo = inset, hi = 1 - inset;
  return {ApplyHomography(h, lo, lo), ApplyHomography(h, hi, lo), ApplyHomography(h, hi, hi),
          ApplyHomography(h, lo, hi)};
}

// What one Detect works in: the candidate the stages build up, the frame's
// accepted areas and rejected regions, and the stages' buffers. The detector
// keeps a pool of them, one per Detect in flight, so that several threads can
// share it; a test that calls the stages directly makes its own.
struct Scratch {
  Candidate candidate;
  std::vector<DetectedArea> areas;
  RowScanBuffers row_scan;  // FindADiff.
  std::vector<RejectedRegion> rejected;
  RingScanBuffers ring_scan;  // InitialScan, QuadsFromScans, BuildPolygon.
  PolygonBuffers polygon;     // BuildPolygon.
  QuadFitBuffers quad_fit;    // PolyToQuad, GrowRegion.
  SideFitBuffers side_fit;    // NestedAndRefined, PolyToQuad, DecodeCandidate, GrowRegion.
  RegionBuffers region;       // GrowRegion.
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_STAGES_H_
