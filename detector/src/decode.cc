// Stage 5, Decode (paper section 4, Figure 6j; spec sections 3, 4 and 7).
#include "decode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "blur_model.h"
#include "candidate.h"
#include "geometry.h"
#include "kernels/kernels.h"
#include "kernels/scalar.h"
#include "refine_corners.h"

namespace chromatag::internal {
namespace {

// Each cell is read as the mean colour of an n x n grid of pixels spanning
// this far either side of its centre (in cells): the middle half of the cell,
// clear of edges blurred by up to about 2 px on 10 px cells. n grows with the
// cell so that the grid's pixels are distinct, which averages sensor and JPEG
// noise over up to 36 pixels.
constexpr double kCellSampleReach = 0.25;
constexpr int kMinCellSamples = 3;
constexpr int kMaxCellSamples = 6;
// Largest mean distance, in cells, between the measured inner ring corners
// and where a family puts them for the family to be considered.
constexpr double kMaxRingMisfitCells = 0.35;
// A bit is corrected only if its cell's shade value lies within this fraction of the
// way from the split to its group's mean (0: on the split, 1: at the mean).
constexpr double kMaxCorrectedCellCertainty = 0.5;
// A colour with at most this many cells is never corrected (16h5's red
// centre has 4). Its midpoint split rests on one or two extreme cells, so
// under blur (which pulls the four adjacent cells together) or noise no cell
// can be judged doubtful: swapped-shade 16h5 tags then decode as the ID one
// red cell away from their complement, with margins and doubts no different
// from true corrected reads.
constexpr int kMaxUncorrectableCells = 4;
// The decision margin guards against reads in which many cells are in
// doubt; how much of it a read needs depends on how far the nearest other
// code is. A read whose nearest other code is at least kFarCodeBits away
// (36h11, minimum distance 11, corrected by up to 2 bits) needs none: that
// many cells would all have to fall on the wrong side together, and the
// corrected cells must still be doubtful ones. An exact read in a family of
// closer codes (16h5) needs kExactReadMarginFactor of it; a corrected one
// all of it. Small, blurred tags, JPEG's 4:2:0 chroma and demosaicing pull
// cells next to the other shade towards the split and lower the margin of
// clean reads: on 2,000 classic and 1,500 camera benchmark frames with no
// margin gate at all every read was the right ID, the lowest margins (0.06)
// included.
constexpr int kFarCodeBits = 9;
constexpr double kExactReadMarginFactor = 0.5;
// A 36h11 read that fails is tried again with each cell's shade value sharpened
// against its four neighbours' by these shares (a neighbour's share of a cell's middle
// under blur of about a third of a cell, and twice that).
constexpr float kCrosstalk[] = {0.08f, 0.16f};
// Reads of a family with close codes (16h5) are checked against a model of
// blur (FitBlurModel): each cell's shade value is its shade's level plus a share (one of
// kBlurShares) of each of its four neighbours' levels, the black ring's
// included, with the four shade levels fitted by least squares; the misfit
// is the largest cell's distance from its prediction over the smaller gap
// between a colour's two shades.
// - A tag printed with its shades swapped shows, within each colour, the
//   complement of its code; for several 16h5 IDs that complement lies within
//   two bits of another ID, and blur or noise can make it read as that ID
//   exactly with a good margin. A read is refused when the complement of some
//   kept ID's code (within kMaxSwappedRivalBits of the observed bits)
//   explains the cells about as well as the read code does (its misfit
//   under kMinSwappedTieRatio times the read's), or, for a read that
//   corrected bits (cells its code does not explain), when the swapped
//   print's misfit is under kMinSwappedRivalRatio times the read's. On
//   16,000 swapped prints in a stress run (detector_conditions_test) the
//   tie ratio took wrong reads from 4 to 2 (misfits 0.445 against 0.448 and
//   0.268 against 0.269); the corrected-read ratio refuses a two-bit
//   correction at 0.33 against 0.36 (decode_test's small blurred prints).
//   On 4,000 camera-set and 4,000 classic frames no tag was lost. The tie
//   ratio was 1.05 while every candidate's inner rings were also refined,
//   which refused one more swapped print by chance (stress frame 570: its
//   inner sides failed); without that, its read (misfit 0.262 against the
//   swapped print's 0.288, a ratio of 1.10) got through. Exact reads of real
//   tags with a swapped rival keep well clear: of the 3,394 that reached the
//   blur model on those 8,000 frames (none a wrong ID), the lowest ratio was
//   1.41. At 1.25 the stress run's wrong reads are back
//   to 2 and those 8,000 frames lose no tag; on the full 10,000 classic
//   frames one small tag (under 30 px) more is refused as a swapped print
//   (5,992 found at 1.05, 5,991 at 1.25).
// - The worst cell is one cell's noise; where the swapped print lies one or
//   two cells from the read, the other cells' noise ties the two worst
//   misfits though the read fits the cells as a whole far better. An exact
//   read is therefore no tie when the swapped prints' root mean square misfit
//   (in shade units, each at its best share) is at least kMinSwappedRmsRatio
//   times the code's. Logged over the camera set's first 8,000 frames and
//   the 2,000 swapped-print stress frames: the swapped prints refused here
//   had ratios up to 1.17 for exact reads (1.32 for corrected ones); the true
//   tags refused had 1.11-3.48, two thirds of them 16h5 ID 25, whose code
//   lies one red cell from a swapped print. At 1.5 the camera set finds 12
//   tags more (5 of 30 px or more at up to 60 degrees, 7 of them ID 25) and
//   the classic set 4, none lost, with no wrong ID on either set; the stress
//   frames let the same 3 swapped prints through as before.
// - A read whose margin is too low is accepted when its code explains every
//   cell to within kMaxCellMisfit, no swapped print comes within
//   kMinSwappedRivalRatio of it, and, if bits were corrected, the margin is
//   at least kMinCorrectedRescueMargin of the gate: blur on small tags pulls
//   cells next to the other shade towards the split. Swapped prints of 16h5
//   under heavy blur and JPEG (16,000 tags in a stress run) got through
//   without those two conditions.
// - Shares larger than blur can carry into a cell's sampled middle are not
//   tried (MaxBlurShare, plus one step): free of that bound, a share of 0.12
//   let a swapped print explain a cleanly read 148 px 16h5 tag (margin 7.7,
//   25 px cells) as well as its own code did, by taking one red-1 cell for
//   a red-0 lifted by its bright green-0 neighbours, and the tag was
//   refused. On the camera set's 8,000 frames the bound found 7 tags more
//   and lost 2; of the 16,000 swapped prints of the stress frames
//   (detector_conditions_test) 3 decode, as without it (a wider blur of
//   3.5 px lost 10 camera-set tags and still let the same 3 through).
constexpr double kMaxCellMisfit = 0.3;
constexpr int kMaxSwappedRivalBits = 3;
constexpr double kMinSwappedRivalRatio = 1.5;
constexpr double kMinSwappedTieRatio = 1.25;
constexpr double kMinSwappedRmsRatio = 1.5;
constexpr double kMinCorrectedRescueMargin = 0.25;

// Mean distance in cells from where `family` puts the green/black and
// red/green corners (1 and 2 cells inside the black square) to the nearest
// measured ones.
double RingMisfit(const TagFamily& family, const cv::Matx33d& image_from_tag,
                  const Candidate& candidate) {
  const int cells = family.black_square_cells();
  const double side = std::sqrt(QuadArea(candidate.quads[kBlackWhite]));
  const double cell_px = side / cells;
  double sum = 0;
  for (int ring = kRedGreen; ring <= kGreenBlack; ++ring) {
    const double inset = (ring == kGreenBlack ? 1.0 : 2.0) / cells;
    for (const cv::Point2d& predicted : InsetSquare(image_from_tag, inset)) {
      double nearest = 1e300;
      for (const auto& measured : candidate.quads[ring])
        nearest = std::min(nearest, cv::norm(measured - predicted));
      sum += nearest;
    }
  }
  return sum / 8.0 / cell_px;
}

// What tells a colour's two shades apart (spec section 3): b*, plus
// kShadeLightness times L*. The spec's green-1 is darker as well as bluer
// than green-0; in both palettes red-1 is also a little lighter than red-0,
// so L* adds to the gap of both colours (iccv17: 8 -> 10 b* units for the
// reds, 11 -> 20 for the greens; default: 55 -> 57, 51.5 -> 55.5). Washed-out
// prints keep the lightness gap when their b* gap shrinks. Read with the
// true corners on the 88 camera-set tags of 30 px or more (up to 60 degrees)
// that the detector lost after FindADiff in 3,000 frames, the payload cells
// split at each colour's midpoint gave 357 wrong bits in b*
// alone, 238 with L* added at weight 1 (275 at 0.5).
constexpr float kShadeLightness = 1.0f;

// The share of a neighbour's colour that reaches a cell's sampled middle
// (kCellSampleReach either side of its centre) through a blur of
// kChromaBlurPx, on cells `cell_px` wide: the mean, over the sampled span,
// of the Gaussian tail beyond the cell's edge. kChromaBlurPx is the blur
// colour suffers in the worst of the benchmark's cameras: optics (sigma up
// to 1.5 px), motion (up to 5 px), demosaicing and JPEG's half-resolution
// chroma, together about 2.5 px; 0.12, the largest share, needs cells of
// 6 px or less, none is left beyond 20 px.
constexpr double kChromaBlurPx = 2.5;
float MaxBlurShare(double cell_px) {
  constexpr int kSteps = 8;
  double sum = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double x = (2.0 * (i + 0.5) / kSteps - 1.0) * kCellSampleReach * cell_px;
    sum += 0.5 * std::erfc((0.5 * cell_px - x) / (kChromaBlurPx * std::sqrt(2.0)));
  }
  return static_cast<float>(sum / kSteps);
}

}  // namespace

PixelSums SumCellGrid(const ImageView& image, cv::Point2d centre, cv::Point2d du, cv::Point2d dv,
                      int samples) {
  CellGrid grid;
  grid.centre = centre;
  grid.du = du;
  grid.dv = dv;
  grid.samples = std::clamp(samples, 2, static_cast<int>(grid.spread.size()));
  for (int i = 0; i < grid.samples; ++i) grid.spread[i] = 2.0 * i / (grid.samples - 1) - 1.0;
  PixelSums sums;
  const int count = grid.samples * grid.samples;
  int k = 0;
  if (image.kernels().add_grid_points && image.OffsetsFit32()) {
    k = image.kernels().add_grid_points(image.frame(), grid, count, &sums);
  }
  for (; k < count; ++k) AddGridPoint(image.frame(), grid, k, &sums);
  return sums;
}

namespace {

// The cell's grid follows the local affine approximation of the homography
// at its centre: exact enough over half a cell, and two projections a cell
// instead of one a sample.
CellSample ReadCell(const ImageView& image, const cv::Matx33d& image_from_tag, int cells, int row,
                    int col, int samples) {
  const double u = (col + 1.5) / cells, v = (row + 1.5) / cells;
  const double reach = kCellSampleReach / cells;
  const cv::Point2d centre = ApplyHomography(image_from_tag, u, v);
  const cv::Point2d du = ApplyHomography(image_from_tag, u + reach, v) - centre;
  const cv::Point2d dv = ApplyHomography(image_from_tag, u, v + reach) - centre;
  const PixelSums sums = SumCellGrid(image, centre, du, dv, samples);
  const int n = sums.n;
  if (n == 0) return {};
  const LabF lab = image.table().Lab(static_cast<uint8_t>((sums.r + n / 2) / n),
                                     static_cast<uint8_t>((sums.g + n / 2) / n),
                                     static_cast<uint8_t>((sums.b + n / 2) / n));
  return {lab.a, lab.b + kShadeLightness * lab.L};
}

// Spec section 3: each colour's cells split at the midpoint of their shade value
// range. Returns the split and the margin: the gap between the two groups
// over their pooled standard deviation (at least one unit).
struct Split {
  float threshold = 0;
  double margin = 0;
  double half_gap = 0;  // Half the distance between the two groups' means.
};

Split SplitShades(const std::vector<float>& values) {
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  Split split;
  split.threshold = 0.5f * (*lo + *hi);
  float max_low = -1e30f, min_high = 1e30f;
  double sum[2] = {0, 0}, sum2[2] = {0, 0};
  int count[2] = {0, 0};
  for (float v : values) {
    const int group = v > split.threshold ? 1 : 0;
    if (group)
      min_high = std::min(min_high, v);
    else
      max_low = std::max(max_low, v);
    sum[group] += v;
    sum2[group] += static_cast<double>(v) * v;
    ++count[group];
  }
  double pooled = 0;
  for (int g = 0; g < 2; ++g) {
    if (count[g]) pooled += sum2[g] - sum[g] * sum[g] / count[g];
  }
  const double spread = std::sqrt(pooled / std::max(1, count[0] + count[1] - 2));
  split.margin = (min_high - max_low) / std::max(1.0, spread);
  if (count[0] && count[1]) split.half_gap = 0.5 * (sum[1] / count[1] - sum[0] / count[0]);
  return split;
}

// Splits each colour's cells at its own midpoint of shade value (`b`: the payload's
// cells, row by row), reads the code, looks it up and checks the margin and
// the corrected cells. Fills *match and *margin.
bool DecodeShades(const DetectorOptions& options, const FamilyDecoder& entry,
                  const std::vector<float>& b, CodeMatch* match, double* margin, RejectReason* why,
                  Code* observed_bits = nullptr) {
  auto reject = [why](RejectReason reason) {
    *why = reason;
    return false;
  };
  const TagFamily& family = *entry.family;
  const int d = family.payload_width();
  std::vector<float> red_b, green_b;
  for (int cell = 0; cell < d * d; ++cell) {
    (family.CellColorAt(cell / d, cell % d) == CellColor::kRed ? red_b : green_b)
        .push_back(b[cell]);
  }
  const Split red = SplitShades(red_b), green = SplitShades(green_b);
  *margin = std::min(red.margin, green.margin);
  // The least any read of this family needs; the read's own need follows.
  if (*margin < options.min_decision_margin * DecisionMarginFactor(family, 0))
    return reject(RejectReason::kLowMargin);

  Code observed = 0;
  for (int cell = 0; cell < d * d; ++cell) {
    // Bit 1 is the higher red (red-1) and the lower green (green-1).
    const bool bit = family.CellColorAt(cell / d, cell % d) == CellColor::kRed
                         ? b[cell] > red.threshold
                         : b[cell] <= green.threshold;
    observed = (observed << 1) | (bit ? 1u : 0u);
  }
  if (observed_bits) *observed_bits = observed;
  if (!entry.decoder->Decode(observed, match)) return reject(RejectReason::kUnknownCode);
  if (*margin < options.min_decision_margin * DecisionMarginFactor(family, match->hamming))
    return reject(RejectReason::kLowMargin);
  // Correct only cells whose shade is in doubt. A cell read clearly as the
  // wrong shade is not noise: a tag printed with its shades swapped shows the
  // complement of its code, and for 16h5 that complement lies within two bits
  // of another ID for 10 of the 28 IDs; it would decode as that ID.
  const Code wrong = observed ^ family.Rotate(family.CodeOf(match->id), match->rotation);
  for (int cell = 0; cell < d * d; ++cell) {
    if (!((wrong >> (d * d - 1 - cell)) & 1u)) continue;
    const bool is_red = family.CellColorAt(cell / d, cell % d) == CellColor::kRed;
    if (static_cast<int>((is_red ? red_b : green_b).size()) <= kMaxUncorrectableCells)
      return reject(RejectReason::kDoubtfulCorrection);
    const Split& split = is_red ? red : green;
    const double doubt = std::abs(b[cell] - split.threshold) / std::max(1e-6, split.half_gap);
    if (doubt > kMaxCorrectedCellCertainty) return reject(RejectReason::kDoubtfulCorrection);
  }
  return true;
}

// The payload's shade values with each cell's share of its four neighbours' taken out
// (the black ring's beyond the payload's edge): b' = (b - k sum) / (1 - 4 k).
std::vector<float> Sharpened(const PayloadGrid& grid, int d, float k) {
  const int w = d + 2;  // The grid includes the black ring.
  std::vector<float> b(d * d);
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const int i = (row + 1) * w + col + 1;
      const float around =
          grid[i - 1].shade + grid[i + 1].shade + grid[i - w].shade + grid[i + w].shade;
      b[row * d + col] = (grid[i].shade - k * around) / (1.f - 4.f * k);
    }
  }
  return b;
}

// The swapped prints (FamilyDecoder::swapped_codes) within
// kMaxSwappedRivalBits of the observed bits.
std::vector<Code> SwappedRivals(const FamilyDecoder& entry, Code observed) {
  std::vector<Code> rivals;
  for (Code swapped : entry.swapped_codes) {
    if (HammingDistance(swapped, observed) <= kMaxSwappedRivalBits) rivals.push_back(swapped);
  }
  return rivals;
}

// The best fits among `rivals` (FitBlurModel): the smallest worst-cell
// misfit and the smallest root mean square misfit in shade units (abs_rms),
// each over every rival; infinite if there are none.
BlurFit FitSwappedPrints(const TagFamily& family, const std::vector<Code>& rivals,
                         const PayloadGrid& grid) {
  BlurFit best;
  for (Code swapped : rivals) {
    const BlurFit fit = FitBlurModel(family, swapped, grid);
    best.worst = std::min(best.worst, fit.worst);
    best.abs_rms = std::min(best.abs_rms, fit.abs_rms);
  }
  return best;
}

// A read that the rules above refuse gets a soft-decision read
// (SoftDecode), first with the blur model (BlurModelRead): every code of the
// family (each kept ID in each orientation) and every swapped print within a
// few bits of the observed bits is fitted to the cells' shade values with the
// blur model (FitBlurModel), and the best fit is taken when it is a code,
// explains the cells (root mean square misfit at most kMaxSoftMisfit of the
// smaller shade gap) and every rival fits clearly worse (kMinSoftRivalRatio).
// The hard read splits each colour at one threshold, so a cell that JPEG's
// 4:2:0 chroma, demosaicing or blur pulls across it is a wrong bit that the
// margin and doubt rules then refuse; the fit weighs each cell by its
// distance from what each code predicts, its neighbours' share included.
// Measured by logging every soft read with the truth on the camera set's
// first 8,000 frames:
// - 16h5 (close codes): reads further than kSoftReadBits (the hard
//   decoder's radius) from the observed bits gave wrong IDs, with rivals
//   1.4-2.3 times worse; within it, the two wrong reads (12 px tags) had
//   rivals 1.09-1.11 times worse. Blurred swapped prints (decode_test,
//   detector_conditions_test) read as an ID whose code lies two bits from
//   theirs with rivals up to 2.5 times worse: rivals must fit twice as
//   badly, and an ID with a swapped print within kSoftMinSwappedBits (10 of
//   the 28) is read this way only where the swapped prints near it fit the
//   cells kMinSwappedRmsRatio times worse than its code
//   (SwappedPrintsFitFarWorse). On the 48,000 swapped prints of stress
//   frames 0-5999 (detector_conditions_test) such reads had 0.93-1.19, all
//   of ID 14 (one red cell from a swapped print); with the check in place
//   of the bare refusal the classic set finds 27 tags more (16-41 px), the
//   camera set 1, none lost and none wrong.
// - 36h11 (far codes): a code within the family's safe radius (5 bits; no
//   other code is that near); none of 174 reads was wrong at misfits up to
//   0.6. A max_hamming set in the options caps it.
// - The decision margin does not gate a soft read (its fit does): it reports
//   the hard read's.
// - A grid placed from rings a third of a cell off read a 36h11 tag
//   with one bit wrong at misfit 0.15, its corners 3.6 px out
//   (detector_scene_test): the rings must sit within kMaxSoftRingMisfitCells.
// - A print whose two reds print alike (print_check_test) read every tag
//   from its greens: each colour's fitted gap must be at least
//   kMinSoftGapBalance of the other's (iccv17's reds are half its greens).
constexpr int kSoftReadBits = 2;
constexpr int kSoftRivalBits = 4;
constexpr int kSoftMinSwappedBits = 3;
constexpr double kMaxSoftRingMisfitCells = 0.25;
constexpr double kMaxSoftMisfit = 0.3;
constexpr double kMinSoftGapBalance = 0.2;
constexpr double kMinSoftRivalRatio(bool close_codes) { return close_codes ? 2.0 : 1.5; }

// Where a swapped print fits the cells this many times better than every
// code near the observed bits, the blur model has found a swapped print, and
// the colour split (which does not model blur) does not overrule it
// (SoftDecode). On the stress frames of swapped prints
// (detector_conditions_test) the split read one as ID 19 where the swapped
// print fitted 1.66 times better than anything else; the camera-set tags that
// refusing wherever a swapped print fits best lost had it at 1.00-1.25.
constexpr double kMinSwappedOverCodeRatio = 1.5;

// The family's codes (each kept ID in each orientation) and swapped prints
// within `rival_bits` of the observed bits, ranked by a score (lower is
// better, infinite where a pattern cannot explain the cells).
struct PatternSearch {
  double best = std::numeric_limits<double>::infinity();
  double rival = std::numeric_limits<double>::infinity();  // The runner-up's score.
  double best_code_score = std::numeric_limits<double>::infinity();
  double best_swapped_score = std::numeric_limits<double>::infinity();
  CodeMatch best_match;  // The best pattern: ID -1 for a swapped print.
  Code best_pattern = 0;
  bool best_is_code = false;
};

// Swapped prints are looked for within `swapped_bits` of the observed bits
// (rival_bits if negative).
template <typename Score>
PatternSearch SearchPatterns(const FamilyDecoder& entry, Code observed, int rival_bits,
                             const Score& score, int swapped_bits = -1) {
  PatternSearch search;
  if (swapped_bits < 0) swapped_bits = rival_bits;
  auto consider = [&](Code pattern, bool is_code, int id, int rotation) {
    const int bits = HammingDistance(pattern, observed);
    if (bits > (is_code ? rival_bits : swapped_bits)) return;
    const double value = score(pattern);
    double& best_of_kind = is_code ? search.best_code_score : search.best_swapped_score;
    best_of_kind = std::min(best_of_kind, value);
    if (value < search.best) {
      search.rival = search.best;
      search.best = value;
      search.best_match = {id, rotation, bits};
      search.best_pattern = pattern;
      search.best_is_code = is_code;
    } else {
      search.rival = std::min(search.rival, value);
    }
  };
  const TagFamily& family = *entry.family;
  for (size_t i = 0; i < entry.oriented_codes.size(); ++i) {
    consider(entry.oriented_codes[i], true, family.kept_ids()[i / 4], static_cast<int>(i % 4));
  }
  for (Code swapped : entry.swapped_codes) consider(swapped, false, -1, 0);
  return search;
}

// Whether a swapped print lies within kSoftMinSwappedBits of `code`.
bool NearASwappedPrint(const FamilyDecoder& entry, Code code) {
  for (Code swapped : entry.swapped_codes) {
    if (HammingDistance(swapped, code) < kSoftMinSwappedBits) return true;
  }
  return false;
}

// Whether the swapped prints near `code` or near the observed bits fit the
// cells (FitBlurModel's abs_rms) at least kMinSwappedRmsRatio times worse
// than `code` does (`code_fit`, its FitBlurModel), as an exact read in the
// blur model's tie must.
bool SwappedPrintsFitFarWorse(const FamilyDecoder& entry, Code observed, Code code,
                              const BlurFit& code_fit, const PayloadGrid& grid) {
  std::vector<Code> rivals = SwappedRivals(entry, observed);
  for (Code swapped : entry.swapped_codes) {
    if (HammingDistance(swapped, code) < kSoftMinSwappedBits) rivals.push_back(swapped);
  }
  return FitSwappedPrints(*entry.family, rivals, grid).abs_rms >=
         kMinSwappedRmsRatio * code_fit.abs_rms;
}

// A far family's (36h11) swapped print differs from every code by more
// than the soft read's reach, but under blur and noise its cells can still
// lie within that reach of another code: a 36h11 tag printed with its
// shades swapped, among detector_conditions_test's stress frames, read as
// ID 247 with five bits corrected while its own pattern lay further than
// five bits from the observed ones. The blur model's read of a far family
// therefore weighs the swapped prints within kFarSwappedRivalBits of the
// observed bits as rivals: each must fit worse than the code by
// kMinSoftRivalRatio, as the codes must. On the camera set's 8,000 frames
// this refused 5 true 36h11 reads (13-45 px), the likelihood-ratio read
// (MisfitRatioRead) took 2 of them back.
constexpr int kFarSwappedRivalBits = 12;

// Fills *match on success; *swapped_fits_best tells whether a swapped print
// fits the cells kMinSwappedOverCodeRatio times better than every code.
bool BlurModelRead(const FamilyDecoder& entry, Code observed, const PayloadGrid& grid,
                   int read_bits, bool close_codes, CodeMatch* match, bool* swapped_fits_best) {
  const TagFamily& family = *entry.family;
  const int rival_bits = close_codes ? kSoftRivalBits : family.max_safe_radius();
  const PatternSearch search = SearchPatterns(
      entry, observed, rival_bits,
      [&](Code pattern) { return FitBlurModel(family, pattern, grid).rms; },
      close_codes ? rival_bits : kFarSwappedRivalBits);
  *swapped_fits_best =
      std::isfinite(search.best_swapped_score) &&
      kMinSwappedOverCodeRatio * search.best_swapped_score <= search.best_code_score;
  if (!search.best_is_code || search.best_match.hamming > read_bits ||
      !(search.best <= kMaxSoftMisfit) ||
      search.rival < kMinSoftRivalRatio(close_codes) * search.best)
    return false;
  const BlurFit fit = FitBlurModel(family, search.best_pattern, grid);
  if (fit.gap_balance < kMinSoftGapBalance) return false;
  if (NearASwappedPrint(entry, search.best_pattern) &&
      !SwappedPrintsFitFarWorse(entry, observed, search.best_pattern, fit, grid))
    return false;
  *match = search.best_match;
  return true;
}

// The payload's shade values summed per colour, for ColourSplitScore.
struct ColourSums {
  Code mask[2] = {0, 0};  // Cells of the colour (0 red, 1 green), as code bits.
  double sum[2] = {0, 0}, sum2[2] = {0, 0};
  int count[2] = {0, 0};
  std::array<float, 64> shade{};  // By code bit: shade[i] is bit i's cell (Code is 64 bits).
};

// The payload's cells of `colour`, as code bits.
Code CellsOf(const TagFamily& family, CellColor colour) {
  const int d = family.payload_width();
  Code cells = 0;
  for (int cell = 0; cell < d * d; ++cell) {
    if (family.CellColorAt(cell / d, cell % d) == colour) cells |= Code{1} << (d * d - 1 - cell);
  }
  return cells;
}

ColourSums SumColours(const TagFamily& family, const PayloadGrid& grid) {
  const int d = family.payload_width(), w = d + 2;
  ColourSums sums;
  sums.mask[0] = CellsOf(family, CellColor::kRed);
  sums.mask[1] = CellsOf(family, CellColor::kGreen);
  for (int cell = 0; cell < d * d; ++cell) {
    const int bit = d * d - 1 - cell;
    const int c = (sums.mask[0] >> bit) & 1u ? 0 : 1;
    const float x = grid[(cell / d + 1) * w + cell % d + 1].shade;
    sums.shade[bit] = x;
    sums.sum[c] += x;
    sums.sum2[c] += static_cast<double>(x) * x;
    ++sums.count[c];
  }
  return sums;
}

// How well `pattern` splits each colour's cells into its two shades: per
// colour, the cells' squared distances from their shade's mean over the
// squared gap between the two means, summed over both colours and divided by
// the cells; infinite if a shade is missing (so a pattern whose 16h5 red
// cells are all one shade is never read this way) or the means are out of
// their order (red-1 lies above red-0, green-1 below green-0). The score is
// a squared ratio: 0.25 is a root mean square of half the gap, and a rival
// 4 times worse lies twice as far from it. Each colour is judged against
// its own gap, so a print whose reds are faded to a few units apart weighs
// its reds' noise against that gap and not against the greens'.
// *balance (if given): the smaller colour's gap over the larger's.
double ColourSplitScore(const ColourSums& sums, Code pattern, double* balance = nullptr) {
  double score = 0, gaps[2] = {0, 0};
  for (int c = 0; c < 2; ++c) {
    Code ones = pattern & sums.mask[c];
    const int n1 = __builtin_popcountll(ones), n0 = sums.count[c] - n1;
    if (n1 == 0 || n0 == 0) return std::numeric_limits<double>::infinity();
    double s1 = 0;
    for (; ones; ones &= ones - 1) s1 += sums.shade[__builtin_ctzll(ones)];
    const double mean1 = s1 / n1, mean0 = (sums.sum[c] - s1) / n0;
    const double gap = c == 0 ? mean1 - mean0 : mean0 - mean1;
    if (!(gap > 0)) return std::numeric_limits<double>::infinity();
    const double sse = sums.sum2[c] - s1 * mean1 - (sums.sum[c] - s1) * mean0;
    score += std::max(0.0, sse) / (gap * gap);
    gaps[c] = gap;
  }
  if (balance) *balance = std::min(gaps[0], gaps[1]) / std::max(gaps[0], gaps[1]);
  return score / (sums.count[0] + sums.count[1]);
}

// The second soft read, for the reads the blur model cannot settle: every
// code of the family and every swapped print scored by ColourSplitScore, the
// best taken when it is a code within the soft read's radius, splits the
// cells well (kMaxColourSplitScore: root mean square within half the gap)
// and every rival splits them clearly worse (kMinColourSplitRivalRatio);
// both colours' gaps present (kMinSoftGapBalance, here of the shades'
// means); and, as for the blur model's read, an ID with a swapped print
// within kSoftMinSwappedBits only where SwappedPrintsFitFarWorse. The
// blur model's misfit is measured against the smaller of the two colours'
// gaps; on a faded print under a cast, dim light and JPEG the reds' gap
// shrinks to a few b* units, and the greens, read cleanly, then count for
// nothing beside the reds' noise. Measured on the camera set's first 8,000
// frames and the classic set's 10,000 (tag_comparison, ChromaTag alone):
// - 36h11 reads of 55-59 px tags with 3-4 wrong bits scored 0.11-0.12, their
//   rivals 3.6-6.2 times worse; the blur model had put their misfit at
//   0.38-0.47 with no rival in reach;
// - with the ratios at 2 (16h5) and 1.5 (36h11) and the score at 0.6, one
//   15 px 16h5 tag read as another ID (score 0.19, its rival 2.3 times
//   worse); with 4 and 3 and 0.25 (the score that the 36h11 reads above
//   pass with twice their own) no read on either set is wrong, and 48 more
//   tags are found on the camera set (21 of them 30 px or more at up to 60
//   degrees), none lost.
// - reads of an ID near a swapped print (10 of 16h5's 28): on the 48,000
//   swapped prints of stress frames 0-5999 (detector_conditions_test) the
//   colour split read 6 as such an ID (4 of them ID 25 or 14, one red cell
//   from theirs), their swapped prints fitting 1.01-1.22 times worse than
//   the code read; the true reads refused on the camera set had 1.23-3.70.
//   At kMinSwappedRmsRatio the camera set finds 17 tags more and the classic
//   set 30, none lost and none wrong, and the stress frames let the same 4
//   swapped prints through as before (by other reads), the reds-alike ones
//   none.
// 36h11's rivals are looked for within kColourSplitRivalBits of the observed
// bits (16h5's among all its codes): the same reads on both sets as with
// every code, at 14 us a read instead of 340.
constexpr double kMaxColourSplitScore = 0.25;
constexpr int kColourSplitRivalBits = 12;
constexpr double kMinColourSplitRivalRatio(bool close_codes) { return close_codes ? 4.0 : 3.0; }

bool ColourSplitRead(const FamilyDecoder& entry, Code observed, const PayloadGrid& grid,
                     int read_bits, bool close_codes, CodeMatch* match) {
  const TagFamily& family = *entry.family;
  const ColourSums sums = SumColours(family, grid);
  const int rival_bits = close_codes ? family.num_bits() : kColourSplitRivalBits;
  const PatternSearch search = SearchPatterns(
      entry, observed, rival_bits, [&](Code pattern) { return ColourSplitScore(sums, pattern); });
  if (!search.best_is_code || search.best_match.hamming > read_bits ||
      !(search.best <= kMaxColourSplitScore) ||
      search.rival < kMinColourSplitRivalRatio(close_codes) * search.best)
    return false;
  double balance = 0;
  ColourSplitScore(sums, search.best_pattern, &balance);
  if (balance < kMinSoftGapBalance) return false;
  if (NearASwappedPrint(entry, search.best_pattern) &&
      !SwappedPrintsFitFarWorse(entry, observed, search.best_pattern,
                                FitBlurModel(family, search.best_pattern, grid), grid))
    return false;
  *match = search.best_match;
  return true;
}

// A print whose two reds print alike (a press that loses their split;
// `chromatag verify --print` fails its sheet) leaves the red cells one shade
// but for noise and the greens' bleed, which the read splits in two anyway.
// A read that corrected bits can then name another ID, the reds' noise
// tipping it. Such a read is refused when another code within `rival_bits`
// of the observed bits, fitted as a print of that kind (FitBlurModel with
// the reds merged: one level fewer), explains the cells better than the
// read's code with both reds (codes within 12 bits for 36h11, all for
// 16h5); or, for 16h5, where merging the read's own reds leaves its misfit
// within kMinRedsFitGain (the reds add little), better than the read's code
// with its reds merged (the greens alone name another code).
// Measured with every read that corrected bits logged:
// - on stress frames of such prints (detector_conditions_test, 2,000 frames
//   of 8 tags a family: 36 wrong 16h5 IDs and 2 wrong 36h11 IDs without this
//   check), every wrong ID but one had a rival of the first kind (the seven
//   logged at 0.12-0.88 of the read's misfit); the one left (a one-bit 16h5
//   read) had reds that gained 1.14 and greens another code explained better;
// - on the camera set's first 8,000 frames and the classic set's 10,000
//   (tag_comparison, every read right), the true reads' nearest rival of
//   the first kind fitted 1.02 times worse or more; the second refuses a
//   blur-model read of a 16h5 tag of 20 px on the classic set (two, with
//   gains of 1.14 and 1.15, when every code is fitted; see below), whose
//   reds were as uninformative as those prints'. Asked
//   of 36h11 too, it refused two true reads on the camera set (21 and 45 px,
//   gains 1.08-1.17) and no wrong one.
// Such a print's cells are its greens and one red level, so a rival that
// explains them better has greens near the observed ones: fitting only the
// codes whose greens lie within kAlikeRedsGreenSlack bits more of them than
// the read's code does refuses the same reads on those stress frames (one
// bit fewer lets one through), where fitting every code cost 17 us a frame
// with tags on the camera set (tag_comparison, AMD EPYC).
constexpr double kMinRedsFitGain = 1.2;
constexpr int kAlikeRedsGreenSlack = 2;

bool AlikeRedsRivalFitsBetter(const FamilyDecoder& entry, Code code, Code observed,
                              const PayloadGrid& grid, bool close_codes) {
  const TagFamily& family = *entry.family;
  const int rival_bits = close_codes ? family.num_bits() : kColourSplitRivalBits;
  const double own = FitBlurModel(family, code, grid).abs_rms;
  // Where the reds add little to the read's fit, its greens must be the
  // best explained (16h5).
  double bar = own;
  if (close_codes) {
    const double own_merged = FitBlurModel(family, code, grid, /*merge_reds=*/true).abs_rms;
    if (own_merged < kMinRedsFitGain * own) bar = own_merged;
  }
  // Rivals whose greens lie more than kAlikeRedsGreenSlack bits further from
  // the observed greens than the read's do are not fitted.
  const Code greens = CellsOf(family, CellColor::kGreen);
  const int own_green_bits = HammingDistance(code & greens, observed & greens);
  for (Code other : entry.oriented_codes) {
    if (other != code &&
        HammingDistance(other & greens, observed & greens) <=
            own_green_bits + kAlikeRedsGreenSlack &&
        HammingDistance(other, observed) <= rival_bits &&
        FitBlurModel(family, other, grid, /*merge_reds=*/true).abs_rms < bar)
      return true;
  }
  return false;
}

// The last read of a family of close codes (16h5; far codes have one too,
// below), for a read every rule
// above refuses, whether for its margin, a correction or a swapped print: a
// likelihood-ratio test between every pattern a tag could show. Each code of
// the family (each kept ID in each orientation) and each swapped print is
// fitted to the payload's shade values with the blur model, each colour's two
// shades in their order (OrderedMisfit: the sum of squared misfits in shade
// units). The best fit is taken when it is a code within kMaxRatioReadBits
// of the observed bits and every other pattern (another ID, another
// orientation, a swapped print) fits worse by at least kMinMisfitRatioTest
// times the cells' noise variance, estimated from the best fit's misfit over
// n - 5 (four levels and a share; fewer levels where a colour's shades were
// merged; at least kMinShadeNoise squared). Where the rules above weigh one
// cell or one colour's gap, this weighs every cell against the noise the tag
// shows, so a faded print's reds, read at a few units apart, count for what
// their noise allows and no more. Unlike the soft reads it asks nothing of
// the balance of the two colours' gaps: a print whose reds print alike is
// read from its greens where they single out one code by that margin (no
// read of such prints named a wrong ID; `chromatag verify` fails them as
// printing their reds alike). Measured with every 16h5 read logged (the test
// statistic computed offline), ring misfit within kMaxSoftRingMisfitCells,
// the largest statistic of a wrong pattern:
// - within two bits of the observed bits: 8.6 on the 3,000 swapped-print
//   stress frames of detector_conditions_test (74,148 reads, every one of a
//   swapped print), 1.4 on the camera set's 8,000 frames, 0.3 on the classic
//   set's 10,000;
// - at three bits: 4.9 on the stress frames, 5.4 on the camera set, 11.9 on
//   the classic set (a 16 px tag).
// At 15 (two bits) and 30 (three) it reads 13 of the camera set's faded 16h5
// tags under 30 px and 4 of 30-50 px on the iccv17 prints that the rules
// above refused; at four bits it found none more.
constexpr int kMaxRatioReadBits = 3;
constexpr double kMinMisfitRatioTest(int bits) { return bits <= 2 ? 15.0 : 30.0; }
constexpr double kMinShadeNoise = 0.5;

// The same test for a family of far codes (36h11), after every other read
// failed: the best code within kMaxFarRatioReadBits of the observed bits
// (beyond the soft read's five; 36h11's codes lie 11 or more apart), every
// code and swapped print within kFarRatioRivalBits fitting worse by
// kMinFarMisfitRatioTest times the noise. Small 36h11 tags lose many cells
// to JPEG's half-resolution chroma and blur (3-4 px cells at 30-40 px).
// Measured with the bar at 0 (every best code read):
// - on detector_conditions_test's stress frames 0-2999, 36h11 printed with
//   its shades swapped and with its reds alike (48,000 tags), 17 wrong IDs
//   (6 to 8 bits corrected), at statistics of 13.0 and less;
// - on the camera set's 8,000 frames no wrong ID.
// At 30, with up to 8 bits read, the camera set finds 30 more 36h11 tags
// (17 of them 30-46 px), none wrong, and the stress frames read no wrong
// ID; reads of up to 6 and 7 bits found 15 and 22 more. With the soft
// read weighing swapped prints further out (kFarSwappedRivalBits), which refuses 3
// of the set's tags that neither read then takes, it finds 4,363 tags
// against 4,336 without the two.
constexpr int kMaxFarRatioReadBits = 8;
constexpr int kFarRatioRivalBits = 16;
constexpr double kMinFarMisfitRatioTest = 30.0;

// The patterns are fitted nearest the observed bits first, and the read is
// given up at the first that fits within the test's bar: most reads that come
// here fail on one of the first few.
bool MisfitRatioRead(const DetectorOptions& options, const FamilyDecoder& entry, Code observed,
                     const PayloadGrid& grid, double ring_misfit, bool close_codes,
                     CodeMatch* match) {
  if (ring_misfit > kMaxSoftRingMisfitCells) return false;
  const TagFamily& family = *entry.family;
  // A max_hamming the user set caps this read too.
  int max_read_bits = close_codes ? kMaxRatioReadBits : kMaxFarRatioReadBits;
  if (options.max_hamming >= 0) max_read_bits = std::min(max_read_bits, options.max_hamming);
  const int rival_bits = close_codes ? family.num_bits() : kFarRatioRivalBits;
  const size_t num_codes = entry.oriented_codes.size();
  auto pattern_at = [&](size_t i) {
    return i < num_codes ? entry.oriented_codes[i] : entry.swapped_codes[i - num_codes];
  };
  // The patterns within reach, nearest the observed bits first.
  const size_t num_patterns = num_codes + entry.swapped_codes.size();
  std::vector<std::pair<int, size_t>> order;
  order.reserve(num_patterns);
  for (size_t i = 0; i < num_patterns; ++i) {
    const int bits = HammingDistance(pattern_at(i), observed);
    if (bits <= rival_bits) order.push_back({bits, i});
  }
  std::sort(order.begin(), order.end());
  // The best code within max_read_bits; the misfits fitted on the way (the
  // nearest patterns, by their place in `order`) are kept for the test.
  std::vector<double> misfit(order.size(), -1.0);
  double best = std::numeric_limits<double>::infinity();
  size_t best_index = num_patterns;
  for (size_t j = 0; j < order.size() && order[j].first <= max_read_bits; ++j) {
    const size_t i = order[j].second;
    if (i >= num_codes) continue;
    misfit[j] = OrderedMisfit(family, pattern_at(i), grid);
    if (misfit[j] < best) best = misfit[j], best_index = i;
  }
  if (best_index == num_patterns) return false;
  const int read_bits = HammingDistance(pattern_at(best_index), observed);
  const double noise = std::max(best / (family.num_bits() - 5), kMinShadeNoise * kMinShadeNoise);
  const double ratio = close_codes ? kMinMisfitRatioTest(read_bits) : kMinFarMisfitRatioTest;
  const double bar = best + ratio * noise;
  for (size_t j = 0; j < order.size(); ++j) {
    const size_t i = order[j].second;
    if (i == best_index) continue;
    const double m = misfit[j] >= 0 ? misfit[j] : OrderedMisfit(family, pattern_at(i), grid, bar);
    if (!(m >= bar)) return false;
  }
  *match = {family.kept_ids()[best_index / 4], static_cast<int>(best_index % 4), read_bits};
  return true;
}

// `grid`: the payload and the black ring around it (FitBlurModel); `ring_misfit`
// the candidate's (RingMisfit). Fills *match on success.
bool SoftDecode(const DetectorOptions& options, const FamilyDecoder& entry, Code observed,
                const PayloadGrid& grid, double ring_misfit, CodeMatch* match) {
  if (ring_misfit > kMaxSoftRingMisfitCells) return false;
  const TagFamily& family = *entry.family;
  const int radius = entry.decoder->radius();
  const bool close_codes = family.min_hamming() - radius < kFarCodeBits;
  // A max_hamming the user set caps the soft read too; the default lets a
  // far family's soft read reach its safe radius.
  const int read_bits = close_codes                ? std::min(kSoftReadBits, radius)
                        : options.max_hamming >= 0 ? radius
                                                   : family.max_safe_radius();
  bool swapped_fits_best = false;
  if (BlurModelRead(entry, observed, grid, read_bits, close_codes, match, &swapped_fits_best))
    return true;
  // The colour split does not model blur, which can carry a swapped 16h5
  // print's cells to another ID's (kMinSwappedOverCodeRatio).
  if (close_codes && swapped_fits_best) return false;
  return entry.colour_split_read &&
         ColourSplitRead(entry, observed, grid, read_bits, close_codes, match);
}

// A candidate's cells as DecodeAs reads them for one family: the payload
// and, read only when needed, the black ring around it (PayloadGrid).
struct CellReader {
  CellReader(const ImageView& view, const cv::Matx33d& from_tag, int square_cells,
             int payload_width)
      : image(view), image_from_tag(from_tag), cells(square_cells), d(payload_width) {}

  const ImageView& image;
  const cv::Matx33d& image_from_tag;
  int cells = 0;  // Across the black square.
  int d = 0;      // Across the payload.
  PayloadGrid grid;
  bool ring_read = false;

  // The black ring around the payload, read with `n` x `n` samples a cell.
  void ReadRing(int n) {
    ring_read = true;
    const int w = d + 2;
    for (int i = 0; i < w; ++i) {
      for (int row : {-1, d})
        grid[(row + 1) * w + i] = ReadCell(image, image_from_tag, cells, row, i - 1, n);
      for (int col : {-1, d})
        grid[i * w + col + 1] = ReadCell(image, image_from_tag, cells, i - 1, col, n);
    }
  }
  // The ring as the blur model uses it (only its mean: few samples a
  // cell do), unless it has been read.
  void ReadRingOnce() {
    if (!ring_read) ReadRing(kMinCellSamples);
  }
};

// Reads the payload's cells into the reader's grid and their shade values
// into b[] (row by row). False unless every red cell is clearly redder than
// every green one.
bool ReadPayload(const DetectorOptions& options, const TagFamily& family, int samples,
                 CellReader* reader, std::vector<float>* b) {
  const int d = reader->d, w = d + 2;
  float min_red_a = 1e30f, max_green_a = -1e30f;
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const CellSample c =
          ReadCell(reader->image, reader->image_from_tag, reader->cells, row, col, samples);
      reader->grid[(row + 1) * w + col + 1] = c;
      (*b)[row * d + col] = c.shade;
      if (family.CellColorAt(row, col) == CellColor::kRed)
        min_red_a = std::min(min_red_a, c.a);
      else
        max_green_a = std::max(max_green_a, c.a);
    }
  }
  return !(min_red_a - max_green_a < 0.5f * static_cast<float>(options.adiff_thresh));
}

// A read's state through DecodeAs's checks: the code matched, its margin,
// the observed bits (before any correction) and the hard read's margin.
struct ReadState {
  CodeMatch match;
  double margin = 0;
  Code observed = 0;
  double read_margin = 0;
};

// For a family of close codes (16h5): the hard read (`decoded`, or the
// ungated one where only its margin failed) checked against the blur model
// and its swapped prints (kBlurShares). False (and *why) when it is refused:
// as a swapped print (*refused too), or for its margin.
bool BlurModelAccepts(const DetectorOptions& options, const FamilyDecoder& entry,
                      const std::vector<float>& b, bool decoded, CellReader* reader,
                      ReadState* read, bool* refused, RejectReason* why) {
  const TagFamily& family = *entry.family;
  // A read without the margin gate (every other check stands) when the
  // margin was too low; then the blur model decides.
  const bool low_margin = !decoded && *why == RejectReason::kLowMargin;
  if (low_margin) {
    DetectorOptions ungated = options;
    ungated.min_decision_margin = 0.0;
    RejectReason ignored;
    decoded =
        DecodeShades(ungated, entry, b, &read->match, &read->margin, &ignored, &read->observed);
  }
  // With no swapped print within kMaxSwappedRivalBits of the read and the
  // margin passed, the blur model has nothing to decide: skip it.
  const std::vector<Code> rivals =
      decoded ? SwappedRivals(entry, read->observed) : std::vector<Code>{};
  if (!decoded || (!low_margin && rivals.empty())) return decoded;
  reader->ReadRingOnce();
  const CodeMatch& match = read->match;
  const Code code = family.Rotate(family.CodeOf(match.id), match.rotation);
  const BlurFit fit = FitBlurModel(family, code, reader->grid);
  const BlurFit swapped = FitSwappedPrints(family, rivals, reader->grid);
  const double misfit = fit.worst, swapped_misfit = swapped.worst;
  // An exact read whose code explains the cells clearly better over all
  // of them than any swapped print does is no tie, whatever its worst cell.
  const bool clear_in_rms =
      match.hamming == 0 && swapped.abs_rms >= kMinSwappedRmsRatio * fit.abs_rms;
  // A corrected read has bits the code does not explain: a swapped
  // print that comes near it in fit is the likelier source.
  if ((swapped_misfit < kMinSwappedTieRatio * misfit && !clear_in_rms) ||
      (match.hamming > 0 && swapped_misfit < kMinSwappedRivalRatio * misfit)) {
    *why = RejectReason::kSwappedPrint;
    *refused = true;
    return false;
  }
  if (low_margin &&
      (!(misfit <= kMaxCellMisfit) || swapped_misfit < kMinSwappedRivalRatio * misfit ||
       (match.hamming > 0 &&
        read->margin < kMinCorrectedRescueMargin * options.min_decision_margin))) {
    *why = RejectReason::kLowMargin;
    return false;
  }
  return true;
}

// The reads for a family of close codes (16h5): the hard read under the
// blur model (BlurModelAccepts); one it refuses otherwise than as a swapped
// print gets the soft read, its margin the hard read's; and one still
// refused, as a swapped print too, the likelihood-ratio read
// (MisfitRatioRead).
bool CloseCodeRead(const DetectorOptions& options, const FamilyDecoder& entry,
                   const std::vector<float>& b, bool decoded, double ring_misfit,
                   CellReader* reader, ReadState* read, bool* refused, RejectReason* why) {
  if (BlurModelAccepts(options, entry, b, decoded, reader, read, refused, why)) return true;
  reader->ReadRingOnce();
  read->margin = read->read_margin;
  if (!*refused &&
      SoftDecode(options, entry, read->observed, reader->grid, ring_misfit, &read->match))
    return true;
  return entry.misfit_ratio_read &&
         MisfitRatioRead(options, entry, read->observed, reader->grid, ring_misfit,
                         /*close_codes=*/true, &read->match);
}

// The reads for a family of far codes (36h11) after the hard read failed.
// Blur, demosaicing and JPEG's chroma mix each cell with its neighbours;
// small cells lose their shade to them. Read again with the neighbours'
// share taken out; then the soft read, its margin the hard read's, and the
// likelihood-ratio read (MisfitRatioRead). Only for families whose hard
// reads stay kFarCodeBits from any other code: sharpening moves cells
// across the split, and a 16h5 tag printed with its shades swapped then
// read as another ID exactly (DetectorConditionsTest).
bool FarCodeRead(const DetectorOptions& options, const FamilyDecoder& entry, int samples,
                 double ring_misfit, CellReader* reader, ReadState* read) {
  reader->ReadRing(samples);
  for (float k : kCrosstalk) {
    RejectReason ignored;
    if (DecodeShades(options, entry, Sharpened(reader->grid, reader->d, k), &read->match,
                     &read->margin, &ignored))
      return true;
  }
  read->margin = read->read_margin;
  return SoftDecode(options, entry, read->observed, reader->grid, ring_misfit, &read->match) ||
         (entry.misfit_ratio_read &&
          MisfitRatioRead(options, entry, read->observed, reader->grid, ring_misfit,
                          /*close_codes=*/false, &read->match));
}

// Fills *detection from a read: its code, margin and corners in the decoded
// orientation.
void FillDetection(const ImageView& image, const TagFamily& family, const Candidate& candidate,
                   const ReadState& read, SideFitBuffers* buffers, Detection* detection) {
  const int cells = family.black_square_cells();
  // The observation is the tag turned `rotation` quarter turns clockwise, so
  // the upright tag's top-left corner is the observed corner `rotation`.
  const int k = read.match.rotation;
  detection->family = &family;
  detection->id = read.match.id;
  detection->hamming = read.match.hamming;
  detection->decision_margin = read.margin;
  // The stages read the black square found with edges at the encoded
  // average (their thresholds were set on it); the reported corners are
  // moved to where the black ring's width says the edges lie (refine_corners.h,
  // RefineReportedQuad). If that fails, the stages' corners are reported.
  Quad reported = candidate.quads[kBlackWhite];
  cv::Matx<double, 8, 8> covariance;
  if (!RefineReportedQuad(image, cells, buffers, &reported, &covariance)) {
    covariance = kUnrefinedCornerSigmaPx * kUnrefinedCornerSigmaPx * cv::Matx<double, 8, 8>::eye();
  }
  for (int i = 0; i < 4; ++i) detection->corners[i] = reported[(i + k) % 4];
  // The covariance's blocks in the same order.
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const int from_i = (i + k) % 4, from_j = (j + k) % 4;
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b)
          detection->corner_covariance(2 * i + a, 2 * j + b) =
              covariance(2 * from_i + a, 2 * from_j + b);
      }
    }
  }
  detection->image_from_tag = UnitSquareToQuad(detection->corners);
  // Inner corners in the same order, where the tag's proportions put them
  // inside the outer ones (one and two cells in). The outer border is the
  // tag's strongest edge and a luminance one, which cameras and JPEG keep at
  // full resolution; the inner borders' edges (green/black, and red/green in
  // R - G) are weaker and chroma is blurred by 4:2:0 and demosaicing. On the
  // camera set (tag_comparison's corner table, 4,000 frames), against the
  // truth: placed, median 0.39 px, 90th percentile 0.87, all within 3 px;
  // located on their own edges, 0.41, 1.10 and 99.5 %.
  detection->green_corners = InsetSquare(detection->image_from_tag, 1.0 / cells);
  detection->red_corners = InsetSquare(detection->image_from_tag, 2.0 / cells);
}

bool DecodeAs(const ImageView& image, const DetectorOptions& options, const FamilyDecoder& entry,
              const Candidate& candidate, const cv::Matx33d& image_from_tag, double ring_misfit,
              SideFitBuffers* buffers, Detection* detection, RejectReason* why,
              bool* fits_swapped_print) {
  const TagFamily& family = *entry.family;
  const int d = family.payload_width();
  const int cells = family.black_square_cells();
  // Grid pixels one apart across the sampled middle of the cell.
  const double cell_px = std::sqrt(QuadArea(candidate.quads[kBlackWhite])) / cells;
  // Clamped in double: a degenerate quad's area can be anything.
  const int samples = static_cast<int>(
      std::clamp<double>(2 * kCellSampleReach * cell_px + 1, kMinCellSamples, kMaxCellSamples));
  CellReader reader(image, image_from_tag, cells, d);
  reader.grid.cells.resize((d + 2) * (d + 2));
  reader.grid.max_blur_share = MaxBlurShare(cell_px);
  std::vector<float> b(d * d);
  if (!ReadPayload(options, family, samples, &reader, &b)) {
    *why = RejectReason::kWeakChroma;
    return false;
  }
  ReadState read;
  bool decoded = DecodeShades(options, entry, b, &read.match, &read.margin, why, &read.observed);
  read.read_margin = read.margin;
  const bool close_codes = family.min_hamming() - entry.decoder->radius() < kFarCodeBits;
  if (close_codes) {
    bool refused = false;
    decoded = CloseCodeRead(options, entry, b, decoded, ring_misfit, &reader, &read, &refused, why);
    *fits_swapped_print = *fits_swapped_print || refused;
  } else if (!decoded) {
    decoded = FarCodeRead(options, entry, samples, ring_misfit, &reader, &read);
  }
  if (!decoded) return false;
  if (read.match.hamming > 0) {
    reader.ReadRingOnce();
    const Code code = family.Rotate(family.CodeOf(read.match.id), read.match.rotation);
    if (AlikeRedsRivalFitsBetter(entry, code, read.observed, reader.grid, close_codes)) {
      *why = RejectReason::kDoubtfulCorrection;
      return false;
    }
  }
  FillDetection(image, family, candidate, read, buffers, detection);
  return true;
}

}  // namespace

std::vector<Code> OrientedCodes(const TagFamily& family) {
  std::vector<Code> codes;
  codes.reserve(4 * family.kept_ids().size());
  for (int id : family.kept_ids()) {
    for (int r = 0; r < 4; ++r) codes.push_back(family.Rotate(family.CodeOf(id), r));
  }
  return codes;
}

std::vector<Code> SwappedCodes(const TagFamily& family) {
  const Code all = family.num_bits() == 64 ? ~Code{0} : (Code{1} << family.num_bits()) - 1;
  std::vector<Code> codes = OrientedCodes(family);
  for (Code& code : codes) code = ~code & all;
  return codes;
}

bool Decode(const ImageView& image, const DetectorOptions& options,
            const std::vector<FamilyDecoder>& families, const Candidate& candidate,
            SideFitBuffers* buffers, Detection* detection, RejectReason* why,
            bool* fits_swapped_print) {
  *why = RejectReason::kNoFamilyFits;
  bool swapped = false;
  const cv::Matx33d image_from_tag = UnitSquareToQuad(candidate.quads[kBlackWhite]);
  // The ring proportions tell the families apart (red centre 2 of 6 cells for
  // 16h5, 4 of 8 for 36h11); try those that fit, best first.
  std::array<std::pair<double, const FamilyDecoder*>, 4> fits;
  size_t n = 0;
  for (const FamilyDecoder& entry : families) {
    const double misfit = RingMisfit(*entry.family, image_from_tag, candidate);
    if (misfit < kMaxRingMisfitCells && n < fits.size()) fits[n++] = {misfit, &entry};
  }
  for (size_t i = 1; i < n; ++i) {  // Insertion sort: at most a few families.
    for (size_t j = i; j > 0 && fits[j].first < fits[j - 1].first; --j)
      std::swap(fits[j], fits[j - 1]);
  }
  for (size_t i = 0; i < n; ++i) {
    // The first family's reason is kept: it fits the rings best.
    RejectReason reason;
    if (DecodeAs(image, options, *fits[i].second, candidate, image_from_tag, fits[i].first, buffers,
                 detection, &reason, &swapped))
      return true;
    if (i == 0) *why = reason;
  }
  if (fits_swapped_print) *fits_swapped_print = *fits_swapped_print || swapped;
  return false;
}

bool DecodeCandidate(const ImageView& image, const DetectorOptions& options,
                     const StageSwitches& switches, const std::vector<FamilyDecoder>& families,
                     SideFitBuffers* buffers, Candidate* candidate, Detection* detection,
                     RejectReason* why) {
  if (Decode(image, options, families, *candidate, buffers, detection, why,
             &candidate->fits_swapped_print))
    return true;
  if (*why != RejectReason::kNoFamilyFits || !switches.refine_corners ||
      !RefineInnerQuads(image, buffers, candidate))
    return false;
  RejectReason again;
  return Decode(image, options, families, *candidate, buffers, detection, &again,
                &candidate->fits_swapped_print);
}

}  // namespace chromatag::internal

namespace chromatag {

double DecisionMarginFactor(const TagFamily& family, int hamming) {
  if (family.min_hamming() - hamming >= internal::kFarCodeBits) return 0.0;
  return hamming == 0 ? internal::kExactReadMarginFactor : 1.0;
}

}  // namespace chromatag
