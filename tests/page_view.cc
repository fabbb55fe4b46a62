#include "page_view.h"

#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/camera.h"

namespace chromatag::testing {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

CameraIntrinsics BarrelCamera() {
  CameraIntrinsics camera;
  camera.fx = 600;
  camera.fy = 603;
  camera.cx = 370.5;
  camera.cy = 244.25;
  camera.distortion = {-0.25, 0.08, 0.001, -0.0005, 0.0};
  return camera;
}

cv::Mat PhotographPage(const PrintedPage& page, const CameraIntrinsics& camera, cv::Size size,
                       const cv::Vec3d& rvec, const cv::Vec3d& tvec, const SceneOptions& effects,
                       const cv::Scalar& background) {
  // The scale the page is seen at, at most: read it from a copy of the page
  // near twice that, so that sampling does not alias.
  const double near_mm = std::max(1e-3, 1000 * tvec[2] - 0.5 * page.bgr.cols / page.px_per_mm);
  const double view_px_per_mm = 2 * std::max(camera.fx, camera.fy) / near_mm;
  // All in linear light, as lens and sensor work.
  cv::Mat source = SrgbToLinearImage(page.bgr);
  while (source.cols > 64 &&
         source.cols * 0.5 / page.bgr.cols * page.px_per_mm > 2 * view_px_per_mm) {
    cv::Mat smaller;
    cv::resize(source, smaller, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    source = smaller;
  }
  const double sx = double(source.cols) / page.bgr.cols * page.px_per_mm;
  const double sy = double(source.rows) / page.bgr.rows * page.px_per_mm;
  // Board metres (x right, y up) -> source pixel coordinates (centres at integers).
  const cv::Matx33d source_from_board(1000 * sx, 0, page.origin_mm[0] * sx - 0.5, 0, -1000 * sy,
                                      page.origin_mm[1] * sy - 0.5, 0, 0, 1);
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  const cv::Matx33d plane(r(0, 0), r(0, 1), tvec[0], r(1, 0), r(1, 1), tvec[1], r(2, 0), r(2, 1),
                          tvec[2]);
  // Undistorted pixels -> source pixels.
  const cv::Matx33d source_from_ideal = source_from_board * (CameraMatrix(camera) * plane).inv();
  // Every pixel of a twice-as-fine view, at its centre, undistorted: the
  // same for every view of one camera, so kept for the next call.
  const cv::Size hi(2 * size.width, 2 * size.height);
  static thread_local struct {
    CameraIntrinsics camera;
    cv::Size size;
    std::vector<cv::Point2d> ideal;
  } cache;
  const CameraIntrinsics& c = cache.camera;
  if (cache.size != size || c.fx != camera.fx || c.fy != camera.fy || c.cx != camera.cx ||
      c.cy != camera.cy || c.model != camera.model || c.distortion != camera.distortion) {
    std::vector<cv::Point2d> pixels;
    pixels.reserve(static_cast<size_t>(hi.area()));
    for (int y = 0; y < hi.height; ++y)
      for (int x = 0; x < hi.width; ++x) pixels.emplace_back((x - 0.5) / 2, (y - 0.5) / 2);
    cache.ideal = UndistortPoints(camera, pixels);
    cache.camera = camera;
    cache.size = size;
  }
  const std::vector<cv::Point2d>& ideal = cache.ideal;
  cv::Mat map(hi, CV_32FC2);
  for (int y = 0, i = 0; y < hi.height; ++y) {
    for (int x = 0; x < hi.width; ++x, ++i) {
      const cv::Vec3d p = source_from_ideal * cv::Vec3d(ideal[i].x, ideal[i].y, 1.0);
      // Behind the camera or beyond the lens's range: off the page.
      const bool ahead = p[2] > 0 && std::isfinite(ideal[i].x) && std::isfinite(ideal[i].y);
      map.at<cv::Vec2f>(y, x) =
          ahead ? cv::Vec2f(static_cast<float>(p[0] / p[2]), static_cast<float>(p[1] / p[2]))
                : cv::Vec2f(-1e6f, -1e6f);
    }
  }
  const cv::Mat linear_background = SrgbToLinearImage(
      cv::Mat(1, 1, CV_8UC3, cv::Scalar(background[0], background[1], background[2])));
  cv::Mat fine, small;
  cv::remap(source, fine, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(linear_background.at<cv::Vec3f>(0, 0)));
  cv::resize(fine, small, size, 0, 0, cv::INTER_AREA);
  cv::Mat frame = LinearToSrgbImage(small);
  ApplyCamera(effects, &frame);
  return frame;
}

cv::Vec3d BoardFacing(double tilt_deg, double axis_deg, double spin_deg) {
  cv::Matx33d face, turn, lean;
  cv::Rodrigues(cv::Vec3d(kPi, 0, 0), face);
  cv::Rodrigues(cv::Vec3d(0, 0, spin_deg * kPi / 180), turn);
  const double a = axis_deg * kPi / 180;
  cv::Rodrigues(cv::Vec3d(std::cos(a), std::sin(a), 0) * (tilt_deg * kPi / 180), lean);
  cv::Vec3d rvec;
  cv::Rodrigues(cv::Matx33d(lean * face * turn), rvec);
  return rvec;
}

void PlaceBoard(const cv::Vec3d& on_board, const cv::Vec3d& in_camera, double tilt_deg,
                double axis_deg, double spin_deg, cv::Vec3d* rvec, cv::Vec3d* tvec) {
  *rvec = BoardFacing(tilt_deg, axis_deg, spin_deg);
  cv::Matx33d r;
  cv::Rodrigues(*rvec, r);
  *tvec = in_camera - r * on_board;
}

}  // namespace chromatag::testing
