// Rendered data sets in the spirit of the paper's (section 5, Figure 8):
// 752x480 colour frames in which a ChromaTag and an AprilTag twin (same
// family, ID, size and plane) lie side by side on one flat card, seen by a
// pinhole camera moving along a path that covers a range of black-square
// sizes and viewing angles of 0 to 75 degrees, in front of natural
// photographs. A share of the frames holds no tag at all.
//
// Two sets (DatasetKind):
// - "classic": 16h5 only, a 2-cell quiet zone, sizes of about
//   15-200 px, two colour conditions (white-balanced, and a strong tungsten
//   cast), exposure x0.55-1.1, blur, noise added to the 8-bit values, JPEG
//   70-95 on every frame. Kinder than a camera; kept pixel-identical.
// - "camera": as hard as real cameras. 16h5 and 36h11 on
//   alternate frames, a 1-cell quiet zone on 40 % of the cards, sizes of
//   about 12-250 px, the tags printed four ways (PrintKind: the default
//   palette exactly and through a CMYK press, the paper's iccv17 shades and
//   those faded further), light on the card of x0.3-1.5 (exposure times
//   light level) falling off across it by up to 1.6x, colour casts of a
//   white balance left wrong (red and blue gains of 0.6-1.5, a quarter of
//   the frames in mixed light; cast.h), a tone curve on top of sRGB,
//   optical and motion blur, shot and read noise in linear light, an RGGB
//   Bayer mosaic demosaiced by OpenCV on a third of the frames, and JPEG
//   60-95 with 4:2:0 chroma on 40 %. A quarter of the frames hold no tag.
//
// Every frame is a pure function of (options, index): frames may be rendered
// in any order and on any thread, and the same seed gives the same pixels.
#ifndef CHROMATAG_BENCH_DATASET_H_
#define CHROMATAG_BENCH_DATASET_H_

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace chromatag::bench {

enum class DatasetKind { kClassic = 0, kCamera = 1 };
const char* DatasetKindName(DatasetKind kind);  // "classic", "camera"
// Parses "classic" or "camera"; nullopt for anything else.
std::optional<DatasetKind> ParseDatasetKind(const std::string& name);
// The tag families a set's frames hold: 16h5 and 36h11 in the camera set,
// 16h5 in the classic one.
std::vector<std::string> DatasetFamilies(DatasetKind kind);

// The paper's two lighting conditions. In the camera set a frame counts as
// white-balanced when its cast is "neutral" and its light not mixed.
enum class ColorCondition {
  kWhiteBalanced = 0,  // "WB": neutral, a few percent of residual cast.
  kColorCast = 1,      // "NWB": a strong tungsten-like cast left uncorrected.
};
inline constexpr int kNumConditions = 2;
const char* ConditionName(ColorCondition condition);  // "WB", "NWB"

// How the camera set's sensor turned its mosaic into colour (OpenCV's
// demosaicing, on 16-bit linear data).
enum class BayerMode { kNone = 0, kBilinear = 1, kEdgeAware = 2 };
inline constexpr int kNumBayerModes = 3;
const char* BayerModeName(BayerMode mode);  // "none", "bilinear", "edge-aware"

// How the camera set's ChromaTags were printed: a palette and what the
// printer did to it. Printers wash colours out; the iccv17 shades are what
// the paper's authors measured on their own prints (spec section 6).
enum class PrintKind {
  kDefault = 0,       // The default palette, printed as its file says.
  kDefaultPress = 1,  // The default palette through a CMYK SWOP press (Ghostscript's
                      // default_cmyk.icc applied with LittleCMS, as the tests' IccPress).
  kIccv17 = 2,        // The iccv17 palette as its file says.
  kIccv17Faded = 3,   // The iccv17 palette with a* and b* scaled by kFadedChroma.
};
inline constexpr int kNumPrintKinds = 4;
inline constexpr double kFadedChroma = 0.8;
// "default", "default-press", "iccv17", "iccv17-faded".
const char* PrintKindName(PrintKind kind);
// The built-in palette the tags of `kind` were generated in.
const char* PrintKindPalette(PrintKind kind);

struct DatasetOptions {
  // Which set; see the top of this file. The defaults below are the classic
  // set's; ForKind gives each set's own.
  DatasetKind kind = DatasetKind::kClassic;
  int width = 752;  // The paper's camera (mvBluefox-200wc).
  int height = 480;
  int num_frames = 10000;  // About 6 minutes for the comparison on 2 cores.
  uint64_t seed = 1;
  // Share of frames with no tag at all, [0, 1].
  double tag_free_share = 0.2;
  // The camera path aims at black squares of this side when seen face on,
  // pixels (log-uniform between the two), and at viewing angles up to
  // max_view_angle_deg. Close views are moved back until the whole sheet fits
  // in the frame, so the largest sizes occur mostly with little camera roll.
  double min_size_px = 15.0;
  double max_size_px = 200.0;
  double max_view_angle_deg = 75.0;
  double focal_px = 640.0;  // About a 60 degree horizontal field of view.
  // Folder of natural photographs (Debian's opencv-doc).
  std::string photo_dir = "/usr/share/doc/opencv-doc/examples/data";
  // Built-in palette the classic set's ChromaTags are printed with (the
  // camera set's follow PrintKind).
  std::string palette = "default";
  // Each output pixel averages supersampling^2 samples (antialiased edges).
  int supersampling = 3;

  // The defaults of `kind`: the camera set has sizes of 12-250 px and a
  // quarter of its frames tag-free.
  static DatasetOptions ForKind(DatasetKind kind);

  bool IsValid(std::string* error) const;
};

// Ground truth of one tag in a frame.
struct TagTruth {
  std::string family;  // "16h5" or "36h11"; empty when the frame has no tag.
  int id = -1;
  // The black square, top-left of the upright tag first, then clockwise
  // (spec section 7); pixel centres at integer coordinates.
  std::array<cv::Point2d, 4> corners;
  // The paper's measures (Figure 9): square root of the black square's area
  // in the image, pixels; angle between the tag's normal and the direction
  // from the tag's centre to the camera, degrees.
  double size_px = 0.0;
  double view_angle_deg = 0.0;
  // camera_from_tag in the spec's tag frame (origin at the tag's centre, x
  // right, y up, z towards the viewer), lengths in black-square sides; and
  // the frame's pinhole camera (square pixels, no distortion).
  cv::Matx33d rotation = cv::Matx33d::eye();
  cv::Vec3d translation;
  double fx = 0.0, cx = 0.0, cy = 0.0;
};

struct FrameTruth {
  int index = 0;
  DatasetKind kind = DatasetKind::kClassic;
  ColorCondition condition = ColorCondition::kWhiteBalanced;
  bool has_tags = false;
  // Of both tags, when has_tags ("" and 0 otherwise).
  std::string family;
  int quiet_zone_cells = 0;
  TagTruth chromatag;  // Valid when has_tags.
  TagTruth apriltag;
  std::string photo;  // File name of the background photograph.
  // How the frame was made, for the per-frame record. The classic set fills
  // the fields it has: cast "neutral" or "tungsten", tone gamma 1, print
  // chroma 0.85 of DatasetOptions::palette, noise_sigma only.
  PrintKind print = PrintKind::kDefault;  // Camera set, frames with tags.
  // The cast at the card's centre (the frame's centre without a card): the
  // white-balance gains on linear red and blue (green's 1; the classic set's
  // gains over green), and its name: camera set CastKindName (cast.h),
  // classic "neutral" or "tungsten".
  std::string cast = "neutral";
  double red_gain = 1.0;
  double blue_gain = 1.0;
  bool mixed_light = false;  // Two sources, their cast blending across the frame.
  double exposure = 1.0;
  double gradient = 1.0;       // Light on the card, brightest over darkest.
  double tone_gamma = 1.0;     // Exponent applied to the sRGB-encoded value.
  double print_chroma = 1.0;   // Classic: ink chroma as a share of the file's.
  double blur_sigma_px = 0.0;  // Gaussian, in linear light.
  double motion_blur_px = 0.0;
  double noise_sigma = 0.0;  // Classic: Gaussian noise on the 8-bit values, levels.
  // Camera: shot noise (signal-to-noise ratio at linear mid-grey 0.18) and
  // read noise (sigma, linear units), both in linear light before encoding.
  double shot_snr = 0.0;
  double read_noise = 0.0;
  BayerMode bayer = BayerMode::kNone;
  int jpeg_quality = 0;  // 0: stored losslessly.
};

struct Frame {
  cv::Mat bgr;  // CV_8UC3, width x height.
  FrameTruth truth;
};

class Dataset {
 public:
  // Loads the photographs and renders the tag textures. Returns nullptr and
  // sets *error when the options are invalid or fewer than four photographs
  // can be read.
  static std::unique_ptr<Dataset> Create(const DatasetOptions& options,
                                         std::string* error = nullptr);
  ~Dataset();

  // Frame `index` in [0, num_frames). Thread-safe; deterministic.
  Frame Render(int index) const;
  // Render(index).truth. Cheap for the camera set (no pixels are made); the
  // classic set renders the frame.
  FrameTruth Truth(int index) const;

  const DatasetOptions& options() const;
  const std::vector<std::string>& photos() const;  // File names used.

 private:
  struct Impl;
  explicit Dataset(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Square root of the area of a quadrilateral (shoelace), pixels.
double QuadSizePx(const std::array<cv::Point2d, 4>& quad);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_DATASET_H_
