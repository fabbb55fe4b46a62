// A synthetic data set in the spirit of the paper's (section 5, Figure 8):
// 752x480 colour frames in which a ChromaTag and an AprilTag 16h5 with the same
// ID lie side by side on one flat sheet, seen by a pinhole camera moving along
// a path that covers black-square sizes of about 15 to 200 px and viewing
// angles of 0 to 75 degrees, in front of natural photographs, under two colour
// conditions (white-balanced, and a strong uncorrected cast), with blur,
// noise and JPEG. A share of the frames holds no tag at all.
//
// Every frame is a pure function of (options, index): frames may be rendered
// in any order and on any thread, and the same seed gives the same pixels.
#ifndef CHROMATAG_BENCH_DATASET_H_
#define CHROMATAG_BENCH_DATASET_H_

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace chromatag::bench {

// The paper's two lighting conditions.
enum class ColorCondition {
  kWhiteBalanced = 0,  // "WB": neutral, a few percent of residual cast.
  kColorCast = 1,      // "NWB": a strong tungsten-like cast left uncorrected.
};
inline constexpr int kNumConditions = 2;
const char* ConditionName(ColorCondition condition);  // "WB", "NWB"

struct DatasetOptions {
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
  // Built-in palette the ChromaTags are printed with.
  std::string palette = "default";
  // Each output pixel averages supersampling^2 samples (antialiased edges).
  int supersampling = 3;

  bool IsValid(std::string* error) const;
};

// Ground truth of one tag in a frame.
struct TagTruth {
  int id = -1;
  // The black square, top-left of the upright tag first, then clockwise
  // (spec section 7); pixel centres at integer coordinates.
  std::array<cv::Point2d, 4> corners;
  // The paper's measures (Figure 9): square root of the black square's area
  // in the image, pixels; angle between the tag's normal and the direction
  // from the tag's centre to the camera, degrees.
  double size_px = 0.0;
  double view_angle_deg = 0.0;
};

struct FrameTruth {
  int index = 0;
  ColorCondition condition = ColorCondition::kWhiteBalanced;
  bool has_tags = false;
  TagTruth chromatag;  // Valid when has_tags.
  TagTruth apriltag;
  std::string photo;  // File name of the background photograph.
  // How the frame was degraded, for the per-frame record.
  double exposure = 1.0;
  double blur_sigma_px = 0.0;
  double motion_blur_px = 0.0;
  double noise_sigma = 0.0;  // 8-bit levels.
  int jpeg_quality = 0;
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
