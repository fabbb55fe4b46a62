#include "chromatag/detector/draw.h"

#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/camera.h"

namespace chromatag {

namespace {

// Drawn at 16x sub-pixel precision so that the lines sit on the corners.
constexpr int kShift = 4;

cv::Point Fixed(const cv::Point2d& p) {
  return cv::Point(cvRound(p.x * (1 << kShift)), cvRound(p.y * (1 << kShift)));
}

int Thickness(const cv::Mat& canvas) {
  return std::max(1, std::min(canvas.cols, canvas.rows) / 400);
}

}  // namespace

void DrawDetections(const std::vector<Detection>& detections, const CameraIntrinsics* camera,
                    double tag_size, cv::Mat* canvas) {
  const auto fixed = Fixed;
  const int thickness = Thickness(*canvas);
  for (const Detection& detection : detections) {
    for (int i = 0; i < 4; ++i) {
      cv::line(*canvas, fixed(detection.corners[i]), fixed(detection.corners[(i + 1) % 4]),
               cv::Scalar(255, 255, 0), thickness, cv::LINE_AA, kShift);
    }
    cv::circle(*canvas, fixed(detection.corners[0]), (3 * thickness + 2) << kShift,
               cv::Scalar(0, 0, 255), cv::FILLED, cv::LINE_AA, kShift);
    cv::Point2d centre(0, 0);
    for (const auto& c : detection.corners) centre += 0.25 * c;
    const std::string label = detection.family->name() + ":" + std::to_string(detection.id);
    cv::putText(*canvas, label, cv::Point(cvRound(centre.x), cvRound(centre.y)),
                cv::FONT_HERSHEY_SIMPLEX, 0.4 * thickness, cv::Scalar(255, 0, 255), thickness,
                cv::LINE_AA);
    if (camera && detection.has_pose && tag_size > 0) {
      const double axis = 0.5 * tag_size;
      const std::vector<cv::Point3d> points = {{0, 0, 0}, {axis, 0, 0}, {0, axis, 0}, {0, 0, axis}};
      const std::vector<cv::Point2d> image =
          ProjectPoints(*camera, points, detection.pose.rvec, detection.pose.tvec);
      const cv::Scalar colors[3] = {{0, 0, 255}, {0, 255, 0}, {255, 0, 0}};
      for (int i = 0; i < 3; ++i) {
        cv::line(*canvas, fixed(image[0]), fixed(image[i + 1]), colors[i], thickness + 1,
                 cv::LINE_AA, kShift);
      }
    }
  }
}

void DrawBoardPose(const BoardPose& pose, const std::string& name, const CameraIntrinsics& camera,
                   double axis_length, cv::Mat* canvas) {
  const int thickness = Thickness(*canvas);
  const std::vector<cv::Point3d> points = {
      {0, 0, 0}, {axis_length, 0, 0}, {0, axis_length, 0}, {0, 0, axis_length}};
  // Nothing to draw when the axes reach behind the camera (a bundle whose
  // origin is off to the side): projected, they would come out mirrored.
  cv::Matx33d r;
  cv::Rodrigues(pose.rvec, r);
  for (const cv::Point3d& p : points) {
    if (!((r * cv::Vec3d(p.x, p.y, p.z) + pose.tvec)[2] > 0)) return;
  }
  const std::vector<cv::Point2d> image = ProjectPoints(camera, points, pose.rvec, pose.tvec);
  const cv::Scalar colors[3] = {{0, 0, 255}, {0, 255, 0}, {255, 0, 0}};
  for (int i = 0; i < 3; ++i) {
    cv::line(*canvas, Fixed(image[0]), Fixed(image[i + 1]), colors[i], 2 * thickness + 1,
             cv::LINE_AA, kShift);
  }
  cv::putText(*canvas, name, cv::Point(cvRound(image[0].x) + 6, cvRound(image[0].y) + 14),
              cv::FONT_HERSHEY_SIMPLEX, 0.5 * thickness, cv::Scalar(255, 255, 255), thickness,
              cv::LINE_AA);
}

void DrawRejected(const std::vector<RejectedCandidate>& rejected, cv::Mat* canvas) {
  const int thickness = Thickness(*canvas);
  const cv::Scalar kStageColors[kNumStages] = {{128, 128, 128}, {0, 140, 255}, {0, 230, 230},
                                               {255, 0, 255},   {0, 0, 255},   {255, 128, 0}};
  for (const RejectedCandidate& r : rejected) {
    const cv::Scalar color = r.reason == RejectReason::kInRejectedRegion
                                 ? kStageColors[0]
                                 : kStageColors[static_cast<int>(r.stage)];
    cv::circle(*canvas, Fixed(r.seed), (thickness + 1) << kShift, color, cv::FILLED, cv::LINE_AA,
               kShift);
    if (r.reason == RejectReason::kInRejectedRegion) continue;
    for (size_t i = 0; i < r.outline.size(); ++i) {
      cv::line(*canvas, Fixed(r.outline[i]), Fixed(r.outline[(i + 1) % r.outline.size()]), color,
               thickness, cv::LINE_AA, kShift);
    }
    cv::putText(*canvas, RejectReasonName(r.reason),
                cv::Point(cvRound(r.centre.x) + 4, cvRound(r.centre.y) - 4),
                cv::FONT_HERSHEY_SIMPLEX, 0.35 * thickness, color, thickness, cv::LINE_AA);
  }
}

}  // namespace chromatag
