// Detector parameters (paper section 4, Algorithm 1), shared by the detector,
// the CLI and the calibration tool.
#ifndef CHROMATAG_DETECTOR_OPTIONS_H_
#define CHROMATAG_DETECTOR_OPTIONS_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace chromatag {

class TagFamily;

// Intrinsics in pixels and lens distortion in OpenCV's two models:
// kPinhole, the radial-tangential model (k1, k2, p1, p2[, k3[, k4, k5, k6]];
// empty for none), and kFisheye, the equidistant model of cv::fisheye
// (exactly k1, k2, k3, k4; Kalibr's "equidistant").
enum class LensModel { kPinhole, kFisheye };

struct CameraIntrinsics {
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;
  std::vector<double> distortion;
  LensModel model = LensModel::kPinhole;

  bool IsValid(std::string* error) const;
};

// "pinhole" or "fisheye".
const char* LensModelName(LensModel model);

// Sets camera's fx, fy, cx and cy from a 3 x 3 camera matrix given row by
// row, which must be [fx 0 cx; 0 fy cy; 0 0 1]. False (and *error naming
// the entry, `k[row][column]`) for any other: a transposed matrix (as
// MATLAB writes it: cx and cy in the bottom row), a skew (not modelled),
// a bottom row other than 0 0 1. Entries within 1e-9 of fx of 0, and of 1
// for the corner, pass. fx and fy themselves are checked by IsValid.
bool IntrinsicsFromMatrix(const double (&k)[9], CameraIntrinsics* camera, std::string* error);

// The smallest a* the detector accepts as a tag's red, in CIELAB a* units,
// seen in the tag's own light (each channel over its quiet zone's white,
// the white put at paper white): the palettes' reds have 40 or more, a
// washed-out print lowers it. As shot, a cast and dim light move a* far
// more (a faded red under a green cast at 0.35 of the light reads 10, in
// its own light 31): a seed paler than this must show a tag's colours in
// its own light before the scans go on. The calibration tool fails prints
// whose reds come close.
inline constexpr double kMinTagRedA = 12.0;

// DetectorOptions::max_green_a lies in [-kMaxGreenALimit, kMaxGreenALimit].
inline constexpr double kMaxGreenALimit = 100.0;

// DetectorOptions::white_balance's gains lie in [kMinWhiteBalanceGain, 1]: a
// channel read at a fifth of another's under the light is a cast beyond what
// a camera's white balance leaves (a tungsten lamp through a daylight
// setting is about a third), and the colour table's error bounds are tested
// down to it.
inline constexpr double kMinWhiteBalanceGain = 0.2;

// The share of DetectorOptions::min_decision_margin that a read of `family`
// at Hamming distance `hamming` from its code must reach: all of it for a
// corrected read of a family of close codes (16h5), half for an exact one,
// none when the nearest other code is 9 or more bits away (36h11).
double DecisionMarginFactor(const TagFamily& family, int hamming);

struct DetectorOptions {
  // Families to look for: "16h5", "36h11" or both. Both by default, as in
  // the CLI and the Python module: a tag of either family is found.
  std::vector<std::string> families = {"16h5", "36h11"};

  // N: FindADiff samples every N-th row and column, in pixels. Tag cells must
  // be at least N/2 pixels wide to be seen. Range [1, 64]; smaller finds
  // smaller tags, larger is faster.
  int step = 4;

  // FindADiff's rows: every row_step-th row; 0 (the default) means every
  // step-th, as in the paper. The speed knob (as AprilTag's quad_decimate
  // is): a red region shorter than this can fall between two sampled rows,
  // so larger is faster and misses more of the smallest and steepest tags
  // (docs/calibration.md gives the measured trade). `step` is not a speed
  // knob: other than 4 it loses FindADiff's fastest path.
  // Range 0 or [1, 64].
  int row_step = 0;

  // The row spacing FindADiff uses: row_step, or step when row_step is 0.
  int sampled_row_step() const { return row_step > 0 ? row_step : step; }

  // ADiffThresh: a rise in a* from the previous sample above this seeds a
  // candidate, in CIELAB a* units. Range (0, 200]. Lower finds fainter tags
  // (washed-out prints) at the cost of more candidates.
  double adiff_thresh = 25.0;

  // BorderThresh: an a* (or L*) difference from the reference colour beyond
  // which a scanned pixel counts as past a border, in CIELAB units. (0, 100].
  double border_thresh = 5.0;

  // M: successive pixels beyond BorderThresh that make a border. [1, 16].
  int border_run = 3;

  // The greenest a* past a candidate's red must be below this for the red to
  // count as enclosed by a tag's green, in CIELAB a* units. [-100, 100].
  // The palettes' greens have a* of -36 (default) or less; white, grey and
  // black next to a red object (a red sign on a wall) sit near 0 and are
  // dropped after one scan. Not 0: under a tungsten cast, on views of 68-75
  // degrees with JPEG, a thin green ring read through the blur comes out at
  // a* 0-8 (4 large tags of the classic set were lost at 0).
  double max_green_a = 8.0;

  // FindADiff's second kind of rise (not in the paper): also seed where a*
  // rises by more than ADiffThresh over two samples from a green one, with
  // both steps rising. A red/green border blurred by the optics, demosaicing
  // or JPEG's 4:2:0 chroma (whose 8 x 8 blocks of half-resolution chroma
  // smear a colour edge over 8 px or more) spreads over two samples, and on a
  // dim card or a washed-out print neither step then reaches ADiffThresh.
  // It finds more of those tags for more candidates in natural scenes (green
  // next to red) and a few per cent more time on tag-free frames
  // (docs/calibration.md gives the measured trade). On by default; off only
  // to trade those tags for speed.
  bool two_step_rises = true;

  // Seeds and scans that only a colour cast or dim light explains (not in
  // the paper), beyond the rises into a pale red that the defaults take:
  // rises over two samples from a green a cast lifted to a* 3, seeds of a
  // red as pale as a* 6, and drops into green of 1.2 times a pale red's own
  // a*. Each such candidate must first show a tag's colours in the light of
  // its own quiet zone (kMinTagRedA) before its scans go on. Finds the tags
  // of a faded print under a green cast in dim light with JPEG (28 of 28
  // tags of a test card; the defaults find 17), for about a tenth more of
  // the median time on tag-free frames, more than the detector's margin
  // over its speed floor there; so off by default (docs/calibration.md).
  bool cast_seeds = false;

  // ConvThresh: BuildPolygon stops when polygon area over the area it could
  // still reach exceeds this ratio. (0, 1).
  double conv_thresh = 0.98;

  // Largest number of bit errors corrected while decoding; -1 picks the
  // family's default: 2 (never above its safe radius), and for a read the
  // hard split refuses, a soft-decision read (the cells fitted to each code
  // near them) up to the safe radius of a family of far codes (36h11: 5),
  // then a likelihood-ratio read (every code and swapped print near the
  // observed bits fitted, the best taken only where all others fit far
  // worse) up to 3 bits for 16h5 and 8 for 36h11. A number set here (at
  // most the family's safe radius) caps all three.
  int max_hamming = -1;

  // Smallest accepted decision margin: the gap between the two b* clusters of
  // a colour relative to their spread, dimensionless. [0, inf). It applies
  // in full to reads that correct bits in a family of close codes (16h5);
  // an exact 16h5 read needs half of it, and a read whose nearest other code
  // is 9 or more bits away (36h11) none (decode.cc says why). A soft-decision
  // read (max_hamming) is judged by how well its code fits the cells
  // instead, and reports the margin of the read it replaced.
  double min_decision_margin = 2.0;

  // The camera's white balance: gains on linear light for R, G, B, applied
  // to every pixel before CIELAB, that make the paper white read neutral
  // under the light the camera works in. `chromatag calibrate` measures
  // them on the calibration sheet's paper (docs/calibration.md). Each in
  // [kMinWhiteBalanceGain, 1], the largest exactly 1: gains only darken
  // channels, so every colour stays in the range the colour table covers.
  // {1, 1, 1}, the default: none, the colours as the camera gave them, and
  // each tag is read against its own white. Folded into the detector's
  // colour table at Create, so a white balance costs nothing per pixel.
  std::array<double, 3> white_balance = {1.0, 1.0, 1.0};

  // Report every rejected candidate (DetectionResult::rejected): where it
  // was, which stage abandoned it and why. Off costs nothing.
  bool report_rejected = false;

  // Time each stage (DetectorSummary::stage_time_us). Each stage a candidate
  // goes through then reads the clock twice (about 20 ns each); on the
  // camera set that adds about 2 % to the median frame without tags, which
  // seeds dozens of candidates. Off, the stage times stay zero; the frame's
  // total (and the poses', DetectorSummary::pose_time_us) is always taken.
  bool time_stages = false;

  // Pose (spec section 7): when both are set, every detection carries the
  // tag's pose in the camera frame. tag_size is the side of the black square
  // in metres (> 0); 0 means no pose.
  std::optional<CameraIntrinsics> camera;
  double tag_size = 0.0;

  bool IsValid(std::string* error) const;
};

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_OPTIONS_H_
