// What dataset.cc (the classic set, options, loading) and camera_set.cc (the
// camera set's conditions) share: the random source, the card's layout, the
// camera path and placement, and Dataset::Impl. Private to the bench library.
#ifndef CHROMATAG_BENCH_SRC_DATASET_IMPL_H_
#define CHROMATAG_BENCH_SRC_DATASET_IMPL_H_

#include <apriltag/apriltag.h>

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/bench/cast.h"
#include "chromatag/bench/dataset.h"
#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag::bench {

// A small portable random source: frames must not depend on the standard
// library's distributions, which differ between implementations.
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  double Uniform(double lo = 0.0, double hi = 1.0) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
  }
  int Index(int n) { return static_cast<int>(Uniform() * n) % n; }
  uint64_t Bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

// SplitMix64 finaliser over (seed, index): independent streams per frame.
uint64_t FrameSeed(uint64_t seed, int index);

float SrgbToLinearF(float v);

// The card: ChromaTag (black square, white quiet zone) on the left, its
// AprilTag twin with the same quiet zone on the right, quiet zones touching.
// Sheet units are black-square sides, origin at the card's centre, x right,
// y down, z into the card.
struct SheetLayout {
  int square_cells = 6;  // Black square: 6 cells for 16h5, 8 for 36h11.
  int quiet_cells = 2;

  int tag_cells() const { return square_cells + 2 * quiet_cells; }  // One tag with its zone.
  int sheet_cells_x() const { return 2 * tag_cells(); }
  int sheet_cells_y() const { return tag_cells(); }
  double chroma_centre_x() const { return -static_cast<double>(tag_cells()) / (2 * square_cells); }
  double april_centre_x() const { return -chroma_centre_x(); }
  double half_x() const { return static_cast<double>(sheet_cells_x()) / (2 * square_cells); }
  double half_y() const { return static_cast<double>(sheet_cells_y()) / (2 * square_cells); }
};

struct Camera {
  cv::Matx33d rotation;  // camera_from_sheet.
  cv::Vec3d translation;
  double fx = 0, cx = 0, cy = 0;

  cv::Point2d Project(const cv::Vec3d& sheet_point) const {
    const cv::Vec3d p = rotation * sheet_point + translation;
    return {fx * p[0] / p[2] + cx, fx * p[1] / p[2] + cy};
  }
  // Maps sheet points (x, y, 0) in tag units to image pixels.
  cv::Matx33d ImageFromSheet() const;
};

// Where the camera path is at frame `index`: smooth triangle waves with
// incommensurate periods (in frames) and seeded phases, plus a little jitter.
// Roll sweeps 0-180 degrees like the paper's servo.
struct PathPoint {
  double size_px, view_deg, azimuth_deg, roll_deg;
};
PathPoint CameraPath(const DatasetOptions& options, int index, Rng& rng);

// Aims at one of the two tags or between them, backs off until the whole
// card fits with a margin, then places it at random in the frame by moving
// the principal point.
Camera PlaceCamera(const DatasetOptions& options, const SheetLayout& layout, const PathPoint& path,
                   Rng& rng);

// Ground truth of the tag centred at sheet x = `centre_x`.
TagTruth TagTruthAt(const Camera& camera, double centre_x, int id);

// Where the card lands in the image: the region of interest (clipped to the
// frame, empty when off it) and the finest sampling it needs in a
// `supersampling`-times finer image, pixels per cell.
struct SheetFootprint {
  cv::Rect roi;
  double needed_ppc = 0.0;
};
SheetFootprint Footprint(const Camera& camera, const SheetLayout& layout, cv::Size frame,
                         int supersampling);

// Warps a premultiplied linear texture of the card (CV_32FC4, `ppc` pixels
// per cell, pixel centres at integers) into the footprint's region of
// interest, supersampled and averaged down: CV_32FC4 of roi.size().
cv::Mat WarpSheet(const cv::Mat& texture, int ppc, const Camera& camera, const SheetLayout& layout,
                  const cv::Rect& roi, int supersampling);

// A normalised line of `length_px` at `angle` (radians) as a filter kernel.
cv::Mat MotionKernel(double length_px, double angle);

// Linear light (CV_32FC3, clipped to [0, 1]) to 8 bits through `table`, whose
// entries encode equal steps of [0, 1] (table.size() - 1 steps).
cv::Mat EncodeThrough(const cv::Mat& linear, const std::vector<uint8_t>& table);

// Printed ink's black is no darker, and the paper no whiter, than these L*
// (spec section 6 measured L* 14 for the authors' black).
inline constexpr double kPrintBlackL = 14.0;
inline constexpr double kPrintWhiteL = 95.0;

// Colours as printed: inks are less saturated than the file (`chroma`, a
// share of the file's a* and b*), black ink is not black and paper not
// perfectly white (spec section 6 measured L* 14 for the authors' black).
TagColors PrintedColors(const Palette& palette, double chroma);

// libapriltag's own picture of a tag (1-cell white border), one byte per
// cell: 0 black, 1 white.
cv::Mat AprilTagPicture(apriltag_family_t* family, int id);

struct Texture {
  cv::Mat linear;  // CV_32FC4: premultiplied linear B, G, R, alpha.
  int pixels_per_cell = 0;
};

// One family of the camera set, with its AprilTag pictures by ID.
struct CameraFamily {
  std::shared_ptr<const TagFamily> family;
  std::vector<cv::Mat> april_pictures;  // By AprilTag ID; kept IDs only.
};

// Everything a camera-set frame is made of, drawn before any pixel work (so
// its truth costs microseconds).
struct CameraPlan {
  FrameTruth truth;
  const CameraFamily* family = nullptr;
  int id = -1;
  SheetLayout layout;
  Camera camera;  // Valid when truth.has_tags.
  int photo = 0;
  uint64_t background_seed = 0;
  FrameCast cast;
  double gradient_angle = 0.0;
  double motion_angle = 0.0;
  uint64_t noise_seed = 0;
};

struct Dataset::Impl {
  DatasetOptions options;
  std::shared_ptr<const TagFamily> family;  // Classic: 16h5.
  std::vector<std::string> photo_names;
  std::vector<cv::Mat> photos;  // CV_8UC3 BGR.
  // Classic: textures[id][level], for kept IDs only.
  std::vector<std::array<Texture, 5>> textures;
  std::vector<float> srgb_to_linear;    // 256 entries.
  std::vector<uint8_t> linear_to_srgb;  // 4096 entries over [0, 1].
  // Camera set.
  std::array<TagColors, kNumPrintKinds> printed_colors;  // By PrintKind.
  std::array<CameraFamily, 2> camera_families;           // 16h5, 36h11.

  cv::Mat LinearBackground(int photo, Rng& rng) const;
  // Classic set.
  Frame RenderClassic(int index) const;
  void DrawSheet(const Camera& camera, int id, Rng& rng, cv::Mat* linear, double* gradient) const;
  cv::Mat Finish(cv::Mat linear, FrameTruth* truth, ColorCondition condition, Rng& rng,
                 uint64_t noise_seed) const;
  // Camera set (camera_set.cc).
  bool LoadCameraFamilies(std::string* error);
  CameraPlan PlanCamera(int index) const;
  Frame RenderCamera(int index) const;
};

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_SRC_DATASET_IMPL_H_
