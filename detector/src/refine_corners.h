// Sub-pixel sides (refine_corners.cc): least-squares lines through edge
// points found along each side, corners where they meet. Internal to the
// detector.
#ifndef CHROMATAG_DETECTOR_SRC_REFINE_CORNERS_H_
#define CHROMATAG_DETECTOR_SRC_REFINE_CORNERS_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "geometry.h"
#include "image_view.h"
#include "kernels/kernels.h"

namespace chromatag::internal {

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

// The part of each side the profiles cover, as fractions of it from its
// first corner: clear of the corners, where the neighbouring side
// interferes. CornerBend samples the same part.
inline constexpr double kSideProfilesStart = 0.12;
inline constexpr double kSideProfilesEnd = 0.88;

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

// The profiles across a side and the edge points on them are the edge
// kernel's (kernels/kernels.h: ProfileSpec, ProfileEdge, kProfileStep).

// How well a fitted side is known: its line, and the variances of its
// offset along its normal at the edge points' centroid and of its angle,
// from the scatter of the kept edge points about it.
struct SideFit {
  Line line;
  double offset_variance = 0.0;  // px^2.
  double angle_variance = 0.0;   // rad^2.
};

// RefineQuad's buffers: the profiles across the four sides and their edge
// points, one side's points found, and its line's residuals (FitLine).
struct SideFitBuffers {
  std::vector<ProfileSpec> spec;
  std::vector<ProfileEdge> edges;
  std::vector<cv::Point2d> points;
  std::vector<double> residual, sorted;
  // When set, RefineQuad fills it with each side's fit (side i runs from
  // corner i to corner i + 1). Left null on the stages' searches, which
  // only need the lines.
  std::array<SideFit, 4>* side_fits = nullptr;
};

// Total least squares line through `points`, then once more without points
// farther than three median residuals (at least half a pixel) from it.
// Works in place (the kept points are moved to the front): it runs for every
// side of every ring, and allocating its scratch cost more than the fit: the
// residuals go into the caller's buffers.
bool FitLine(std::vector<cv::Point2d>* points, std::vector<double>* residual_buffer,
             std::vector<double>* sorted_buffer, Line* line);

// The covariance of the four corners where the sides meet (corner i on sides
// i - 1 and i), as x0, y0, x1, y1, ...: each side's offset and angle errors
// carried to the corners it ends at, independent from side to side. px^2.
cv::Matx<double, 8, 8> CornerCovariance(const std::array<SideFit, 4>& sides, const Quad& quad);

// What the reported corners' errors are made of, as standard deviations
// (px, or shares): the edge points' scatter about the sides
// (CornerCovariance, which counts the neighbouring profiles as independent
// and so overstates it), the share between the two edge conventions
// (RefineReportedQuad), a floor on each coordinate, the whole quad grown or
// shrunk (the tone curve and blur move every edge the same way), and terms
// that grow with how unevenly the two conventions move the four sides (px):
// a motion blur widens only the sides across the motion, and shifts and
// jitters the corners. Fitted by maximum likelihood to the corner errors
// against the truth of the camera set's tags of 30 px and more (8,000
// frames, 4,257 tags; docs/pose.md, "Uncertainty"): scatter 0.65, uneven
// jitter 0.4 and shift 0.65, the rest as below; then those three lowered by
// a quarter to a third, which brings the pose covariance's spread on every
// axis to 0.8 or more on those frames.
struct CornerNoiseModel {
  double scatter = 0.45;
  double share = 0.25;
  double floor_px = 0.034;
  double grow_px = 0.092;
  double uneven_each = 0.3;
  double uneven_shift = 0.5;
};
inline constexpr CornerNoiseModel kCornerNoise;

// How a quad's four corners (x0, y0, x1, ...) move when the whole quad
// shifts by a pixel in x or in y, and when it grows by a pixel (each corner
// away from its centre): the modes of error the corner covariance and the
// pose covariance share.
inline const cv::Vec<double, 8> kQuadShiftX(1, 0, 1, 0, 1, 0, 1, 0);
inline const cv::Vec<double, 8> kQuadShiftY(0, 1, 0, 1, 0, 1, 0, 1);
cv::Vec<double, 8> QuadGrowth(const Quad& quad);

// The covariance of the corners RefineReportedQuad reports (CornerCovariance's
// order and units), from the linear-light outer sides' fits, the quads found
// at the `encoded` average and in `linear` light, and kCornerNoise.
cv::Matx<double, 8, 8> ReportedCornerCovariance(const std::array<SideFit, 4>& sides,
                                                const Quad& encoded, const Quad& linear);

// Corners reported without RefineReportedQuad (a cell of a pixel or less, or
// an outer border it could not locate in linear light): standard deviation
// per coordinate, px (corners at the encoded average are about this far
// off on the camera set).
inline constexpr double kUnrefinedCornerSigmaPx = 0.5;
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

// RefineOuterQuad moves the black/white quad (the reported corners and the
// homography); RefineInnerQuads the green/black and red/green ones, which
// only Decode's ring proportions read (DecodeCandidate refines them when the
// rough ones fit no family). False if a side has too few edge points to fit, a
// corner jumps or the quad turns concave; the ring's cell must exceed a pixel.
bool RefineOuterQuad(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate);
bool RefineInnerQuads(const ImageView& image, SideFitBuffers* buffers, Candidate* candidate);
// The reported corners of a decoded tag whose black square has `cells`
// cells: `quad` (its black/white quad as the stages found it, edges at the
// encoded average) moved towards where its edges lie in linear light, as
// far as the black ring says. Where an image was blurred decides where its
// edges lie between their levels: a lens blurs light (linear light is
// right), software that resizes or warps an sRGB image blurs its encoded
// values (the encoded average is right). The black ring is one cell wide:
// its outer and inner borders, each located both ways, are mixed in the
// share that gives it that width (as far as the ring is resolved:
// ResolvedShare; a camera's share, linear light, when the inner border
// cannot be located), and the outer corners in the same share. False (quad
// untouched) when a cell is a pixel or less, or the outer border cannot be
// located in linear light. On success, *covariance (when given) is the
// corners' covariance (CornerCovariance's order and units):
// ReportedCornerCovariance; its doubt about the share is the same whether
// the ring measured it or a camera's was taken (on a frame blurred in
// software, an unresolved ring's corners lie about four of its standard
// deviations out).
bool RefineReportedQuad(const ImageView& image, int cells, SideFitBuffers* buffers, Quad* quad,
                        cv::Matx<double, 8, 8>* covariance = nullptr);

// The black ring tells the two blurs apart only while it is resolved: when
// the blur is a large part of a cell, its middle never reaches black, and its
// inner border (green against that raised black, a small step) drifts
// inwards either way, so the ring always looks too wide and the share it
// gives falls to 0 (the encoded average), wrong for a camera's frames by up
// to a pixel. How far the outer border in linear light lies outside the one at
// the encoded average (`spread`, px) grows with the blur; where a cell is
// kUnresolvedRingCells spreads or fewer, the share is a camera's (1, linear
// light), and it moves linearly to the ring's own (`ring_share`) at
// kResolvedRingCells. A one-dimensional model of the ring (lens blur of 0.5-2
// px, cells of 2.5-12 px) showed its share going wrong below 7.3 and right
// above 8.6; the bounds are set between what the camera set's small tags
// (pure lens blur) and the board test's far tags (a page resampled in
// encoded values, then a lens blur) each measured best. A frame blurred in
// software that much and that small (its ring unresolved) is reported too
// large: a 24 px tag blurred by 2 px, by 1.2 px per side
// (RefineQuadTest.AnUnresolvedRingTakesACamerasBlur). `cell` and `spread`
// are the whole quad's: a steep tag's far side may be less resolved than
// they say.
inline constexpr double kUnresolvedRingCells = 6.5;
inline constexpr double kResolvedRingCells = 9.5;
double ResolvedShare(double ring_share, double cell, double spread);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_REFINE_CORNERS_H_
