// Synthetic detector scenes with exact ground truth: tags rendered by the
// generator (RasterizeTag), placed in 3D in front of a pinhole camera, warped
// into a background with the resulting homography (supersampled, then
// area-averaged, so edges are antialiased like a camera's), then optionally
// blurred, colour-cast, noised and JPEG-compressed.
#ifndef CHROMATAG_TESTS_SYNTHETIC_SCENE_H_
#define CHROMATAG_TESTS_SYNTHETIC_SCENE_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"

namespace chromatag::testing {

struct SceneTag {
  std::string family = "16h5";
  int id = 0;
  // Side of the black square in pixels when seen face-on at the tag's centre
  // depth.
  double black_square_px = 100;
  cv::Point2d centre{0, 0};  // In scene pixels.
  double rotation_deg = 0;   // In-plane, clockwise on screen.
  double tilt_deg = 0;       // Out of plane, about an in-plane axis...
  double tilt_axis_deg = 0;  // ...at this angle from the x axis.
  // Camera distance in tag sizes; smaller means stronger perspective.
  double distance = 4.0;
  std::string palette = "default";
  bool swap_shades = false;  // Print red-1 as red-0 and green-1 as green-0, and back.
  bool reds_alike = false;   // Print red-1 as red-0: a press that loses the reds' split.
  int quiet_zone_cells = 2;
  // As printed: the four chromatic shades' a* and b* scaled by this (printers
  // desaturate), in (0, 1].
  double print_chroma = 1.0;
};

// How a colour camera's sensor is read out.
enum class Demosaic {
  kNone,       // Three values per pixel.
  kBilinear,   // An RGGB Bayer mosaic, demosaiced bilinearly (OpenCV).
  kEdgeAware,  // The same, demosaiced with OpenCV's edge-aware method.
};

struct SceneOptions {
  int width = 320;
  int height = 240;
  // Background: a smooth light-grey gradient, or this BGR image resized to fit.
  cv::Mat background;
  double blur_sigma = 0;  // Gaussian blur, scene pixels (0: none).
  // Blur in linear light, as a camera's optics do, rather than on the sRGB
  // values: dark rings then look thinner.
  bool blur_in_linear_light = false;
  double noise_sigma = 0;   // Gaussian noise, 8-bit units.
  cv::Vec3d gain{1, 1, 1};  // Per-channel R, G, B multipliers: a colour cast.
  int jpeg_quality = 0;     // Encoded and decoded as JPEG last, 1-100 (0: not).
  unsigned seed = 1;
  // A camera in linear light: when set, exposure, `gain`, blur and noise act
  // on linear values (as light, optics and sensor do), an optional Bayer
  // mosaic is demosaiced, and the sRGB curve is followed by the extra tone
  // curve v^tone_gamma. noise_sigma is then in 8-bit units of the linear
  // value at full scale (read noise), plus shot noise of `shot_noise` full
  // scale at full scale (variance proportional to the signal).
  bool linear_camera = false;
  double exposure = 1.0;
  double tone_gamma = 1.0;
  double shot_noise = 0.0;
  Demosaic demosaic = Demosaic::kNone;
};

struct TagTruth {
  std::string family;
  int id = 0;
  // Black square corners, top-left of the upright tag first, clockwise;
  // pixel centres at integers.
  std::array<cv::Point2d, 4> corners;
};

struct Scene {
  cv::Mat bgr;  // CV_8UC3.
  std::vector<TagTruth> truth;
};

Scene RenderScene(const std::vector<SceneTag>& tags, const SceneOptions& options);

// Detector options with the pinhole camera RenderScene sees `tag` through
// (principal point `principal`, its centre in the image) and a tag size of
// one black square: poses come out in tag sizes.
DetectorOptions PoseOptionsFor(const SceneTag& tag, const cv::Point2d& principal);

// What RenderScene does to the rendered frame (8-bit BGR), in place: the
// camera of `options` (light, blur, cast, noise, mosaic, tone, JPEG); its
// size and background are not used.
void ApplyCamera(const SceneOptions& options, cv::Mat* bgr);

// 8-bit sRGB (BGR) to linear light (CV_32FC3, [0, 1]) and back, rounded.
cv::Mat SrgbToLinearImage(const cv::Mat& bgr);
cv::Mat LinearToSrgbImage(const cv::Mat& linear);

// Largest distance between corresponding corners.
double MaxCornerError(const std::array<cv::Point2d, 4>& a, const std::array<cv::Point2d, 4>& b);

// Where the tag of `truth` has the corners of the square `inset_cells` cells
// inside its black square of `cells` cells (1: the green/black border, 2:
// the red/green one), in the same order: the scenes are plane projections,
// so the black square's homography places them.
std::array<cv::Point2d, 4> InnerCorners(const TagTruth& truth, int cells, int inset_cells);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_SYNTHETIC_SCENE_H_
