// A printed page photographed by a camera with a known lens: each pixel of
// the view is traced through the lens model (distortion undone) and the
// plane's homography back onto the page, sampled at twice the resolution
// and averaged down in linear light (as lens and sensor work), then the
// camera's blur, noise and JPEG (ApplyCamera).
// For camera calibration tests and the calibration benchmark, where the
// truth is the camera itself.
#ifndef CHROMATAG_TESTS_PAGE_VIEW_H_
#define CHROMATAG_TESTS_PAGE_VIEW_H_

#include <array>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"
#include "synthetic_scene.h"

namespace chromatag::testing {

struct PrintedPage {
  cv::Mat bgr;  // The page as printed, BGR.
  double px_per_mm = 0;
  // Where the board frame's origin lies on the page (mm from its top-left
  // corner); the board's x runs right and its y up the page, z out of it.
  std::array<double, 2> origin_mm{0.0, 0.0};
};

// The camera of the calibration tests and of docs/camera-calibration.md's
// example: 752 x 480, fx 600, fy 603, the principal point off the image's
// centre at (370.5, 244.25), strong barrel distortion (k1 -0.25, k2 0.08)
// and a little tangential (p1 0.001, p2 -0.0005).
CameraIntrinsics BarrelCamera();

// The page as `camera` sees it with camera_from_board (rvec, tvec), metres,
// in a `size` frame; `background` where the page is not. `effects` is the
// camera after the lens (its width, height and background are not used).
cv::Mat PhotographPage(const PrintedPage& page, const CameraIntrinsics& camera, cv::Size size,
                       const cv::Vec3d& rvec, const cv::Vec3d& tvec, const SceneOptions& effects,
                       const cv::Scalar& background = cv::Scalar(95, 110, 125));

// The board facing the camera (its z towards it), tilted by `tilt_deg`
// about an in-plane axis at `axis_deg` from the camera's x axis, turned
// `spin_deg` in its plane: camera_from_board's rotation as a Rodrigues
// vector.
cv::Vec3d BoardFacing(double tilt_deg, double axis_deg, double spin_deg = 0.0);

// camera_from_board (rvec, tvec) that puts board point `on_board` at
// `in_camera`, the board turned as BoardFacing(tilt_deg, axis_deg, spin_deg).
void PlaceBoard(const cv::Vec3d& on_board, const cv::Vec3d& in_camera, double tilt_deg,
                double axis_deg, double spin_deg, cv::Vec3d* rvec, cv::Vec3d* tvec);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_PAGE_VIEW_H_
