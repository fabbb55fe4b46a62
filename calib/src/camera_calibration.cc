#include "chromatag/calib/camera_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/board.h"

namespace chromatag {
namespace {

// One view's corners: per board tag seen, its twelve corners on the board
// (z = 0) and in the image.
struct ViewPoints {
  std::vector<int> detection;  // Index into the view's detections, per tag.
  std::vector<std::vector<cv::Point3f>> board;
  std::vector<std::vector<cv::Point2f>> image;
};

std::vector<cv::Point2f> RingCorners(const Detection& d) {
  std::vector<cv::Point2f> points;
  for (const auto* ring : {&d.corners, &d.green_corners, &d.red_corners}) {
    for (const cv::Point2d& p : *ring)
      points.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
  }
  return points;
}

template <typename T>
std::vector<T> Flatten(const std::vector<std::vector<T>>& parts) {
  std::vector<T> all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

double Rms(const std::vector<cv::Point3f>& board, const std::vector<cv::Point2f>& image,
           const cv::Mat& rvec, const cv::Mat& tvec, const cv::Mat& k, const cv::Mat& d) {
  std::vector<cv::Point2f> projected;
  cv::projectPoints(board, rvec, tvec, k, d, projected);
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) {
    const cv::Point2f e = projected[i] - image[i];
    sum += e.x * e.x + e.y * e.y;
  }
  return image.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(image.size()));
}

}  // namespace

std::optional<CameraCalibration> CalibrateCamera(const Board& board,
                                                 const std::vector<CalibrationView>& views,
                                                 cv::Size image_size,
                                                 const CameraCalibrationOptions& options,
                                                 std::string* error) {
  const auto fail = [&](const std::string& message) -> std::optional<CameraCalibration> {
    if (error) *error = message;
    return std::nullopt;
  };
  if (!board.IsValid(error)) return std::nullopt;
  if (image_size.width <= 0 || image_size.height <= 0) return fail("the image size is empty");
  for (const BoardTag& tag : board.tags) {
    if (std::abs(tag.translation[2]) > 1e-9 || std::abs(tag.rotation(2, 2) - 1.0) > 1e-9)
      return fail("camera calibration needs a planar board (every tag at z = 0, facing +z)");
  }
  CameraCalibration result;
  result.image_size = image_size;
  std::vector<ViewPoints> points(views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    CalibrationViewResult& out = result.views.emplace_back();
    out.name = views[v].name;
    for (size_t i = 0; i < views[v].detections.size(); ++i) {
      const Detection& d = views[v].detections[i];
      if (d.family == nullptr) continue;
      const int index = board.Find(d.family->name(), d.id);
      if (index < 0) continue;
      std::vector<cv::Point3f> on_board;
      for (const cv::Point3d& p : BoardTagCorners(board.tags[index], *d.family))
        on_board.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), 0.f);
      points[v].detection.push_back(static_cast<int>(i));
      points[v].board.push_back(std::move(on_board));
      points[v].image.push_back(RingCorners(d));
    }
  }
  const int flags = options.fit_k3 ? 0 : cv::CALIB_FIX_K3;
  cv::Mat k, d;
  std::vector<cv::Mat> rvecs, tvecs;
  // Fits the views in `used` (their tags' corners); false with fewer than three.
  const auto fit = [&](const std::vector<size_t>& used, cv::Mat* std_dev) {
    if (used.size() < 3) return false;
    std::vector<std::vector<cv::Point3f>> object;
    std::vector<std::vector<cv::Point2f>> image;
    for (size_t v : used) {
      object.push_back(Flatten(points[v].board));
      image.push_back(Flatten(points[v].image));
    }
    k = cv::Mat();
    d = cv::Mat();
    cv::Mat extrinsic_dev, per_view;
    result.rms_px = std_dev
                        ? cv::calibrateCamera(object, image, image_size, k, d, rvecs, tvecs,
                                              *std_dev, extrinsic_dev, per_view, flags)
                        : cv::calibrateCamera(object, image, image_size, k, d, rvecs, tvecs, flags);
    return true;
  };
  std::vector<size_t> used;
  const auto usable = [&](size_t v) {
    if (static_cast<int>(points[v].board.size()) >= options.min_tags_per_view) return true;
    result.views[v].why_not = std::to_string(points[v].board.size()) +
                              " board tag(s) seen (needs " +
                              std::to_string(options.min_tags_per_view) + ")";
    return false;
  };
  for (size_t v = 0; v < views.size(); ++v)
    if (usable(v)) used.push_back(v);
  if (!fit(used, nullptr)) return fail("fewer than three views show enough of the board");
  // Tags whose corners disagree with the others in their view under the
  // first fit's camera (EstimateBoardPose's robust pose: a misread ID pulls
  // the fitted view, not this) leave the view; views that still fit badly
  // leave the calibration.
  CameraIntrinsics first;
  first.fx = k.at<double>(0, 0);
  first.fy = k.at<double>(1, 1);
  first.cx = k.at<double>(0, 2);
  first.cy = k.at<double>(1, 2);
  first.distortion.assign(d.ptr<double>(), d.ptr<double>() + d.total());
  std::vector<size_t> kept;
  for (size_t v : used) {
    ViewPoints& view = points[v];
    BoardPose pose;
    if (EstimateBoardPose(views[v].detections, board, first, &pose)) {
      for (size_t t = view.board.size(); t-- > 0;) {
        const int detection = view.detection[t];
        if (std::find(pose.detections_rejected.begin(), pose.detections_rejected.end(),
                      detection) == pose.detections_rejected.end())
          continue;
        result.views[v].tags_left_out.push_back(views[v].detections[detection].id);
        view.board.erase(view.board.begin() + t);
        view.image.erase(view.image.begin() + t);
        view.detection.erase(view.detection.begin() + t);
      }
    }
    if (usable(v)) kept.push_back(v);
  }
  if (!fit(kept, nullptr)) return fail("fewer than three views agree with one camera");
  used.clear();
  for (size_t u = 0; u < kept.size(); ++u) {
    const size_t v = kept[u];
    const double rms =
        Rms(Flatten(points[v].board), Flatten(points[v].image), rvecs[u], tvecs[u], k, d);
    if (rms > options.max_rms_px) {
      char why[96];
      std::snprintf(why, sizeof why, "reprojects at %.2f px rms (limit %.2f)", rms,
                    options.max_rms_px);
      result.views[v].why_not = why;
    } else {
      used.push_back(v);
    }
  }
  cv::Mat std_dev;
  if (!fit(used, &std_dev)) return fail("fewer than three views agree with one camera");
  for (size_t u = 0; u < used.size(); ++u) {
    CalibrationViewResult& out = result.views[used[u]];
    out.used = true;
    out.tags = static_cast<int>(points[used[u]].board.size());
    out.rms_px = Rms(Flatten(points[used[u]].board), Flatten(points[used[u]].image), rvecs[u],
                     tvecs[u], k, d);
    out.rvec = cv::Vec3d(rvecs[u].ptr<double>());
    out.tvec = cv::Vec3d(tvecs[u].ptr<double>());
  }
  result.camera.fx = k.at<double>(0, 0);
  result.camera.fy = k.at<double>(1, 1);
  result.camera.cx = k.at<double>(0, 2);
  result.camera.cy = k.at<double>(1, 2);
  result.camera.distortion.assign(d.ptr<double>(), d.ptr<double>() + 5);
  for (int i = 0; i < 9 && i < std_dev.rows; ++i) {
    // OpenCV's order: fx, fy, cx, cy, k1, k2, p1, p2, k3, ...
    result.std_dev.push_back(std_dev.at<double>(i));
  }
  return result;
}

}  // namespace chromatag
