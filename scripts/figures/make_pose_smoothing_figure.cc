// The figure behind docs/pose.md's "Pose over time": the rendered sweep of
// tests/pose_sweep.h, each frame's pose and the PoseFilter's against the
// truth, drawn as two plots (rotation error, depth error) into a PNG, and
// the jitter of each printed.
//
//   build/scripts/figures/make_pose_smoothing_figure docs/images/pose_smoothing.png
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/pose_filter.h"
#include "pose_sweep.h"

namespace {

using namespace chromatag;

constexpr double kPi = 3.14159265358979323846;

// One plot: `raw` as grey dots, `smooth` as a blue line, over the frames;
// values clipped to [lo, hi].
void Plot(cv::Mat* canvas, cv::Rect box, const std::string& title, const std::vector<double>& raw,
          const std::vector<double>& smooth, double lo, double hi) {
  cv::rectangle(*canvas, box, cv::Scalar(160, 160, 160), 1);
  const auto at = [&](size_t i, double v) {
    const double x = box.x + box.width * i / std::max<size_t>(1, raw.size() - 1);
    const double y = box.y + box.height * (1 - (std::clamp(v, lo, hi) - lo) / (hi - lo));
    return cv::Point(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)));
  };
  const int zero = at(0, 0.0).y;
  cv::line(*canvas, {box.x, zero}, {box.x + box.width, zero}, cv::Scalar(200, 200, 200), 1);
  for (size_t i = 0; i < raw.size(); ++i) {
    if (std::isfinite(raw[i])) cv::circle(*canvas, at(i, raw[i]), 2, cv::Scalar(150, 150, 150), -1);
  }
  for (size_t i = 1; i < smooth.size(); ++i) {
    if (std::isfinite(smooth[i - 1]) && std::isfinite(smooth[i]))
      cv::line(*canvas, at(i - 1, smooth[i - 1]), at(i, smooth[i]), cv::Scalar(200, 90, 20), 2,
               cv::LINE_AA);
  }
  cv::putText(*canvas, title, {box.x, box.y - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(40, 40, 40), 1, cv::LINE_AA);
  char text[32];
  std::snprintf(text, sizeof text, "%+g", hi);
  cv::putText(*canvas, text, {box.x - 46, box.y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
              cv::Scalar(80, 80, 80), 1, cv::LINE_AA);
  std::snprintf(text, sizeof text, "%+g", lo);
  cv::putText(*canvas, text, {box.x - 46, box.y + box.height}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
              cv::Scalar(80, 80, 80), 1, cv::LINE_AA);
}

double Jitter(const std::vector<double>& v) {
  double mean = 0, n = 0, sum = 0;
  for (double x : v)
    if (std::isfinite(x)) mean += x, ++n;
  mean /= n;
  for (double x : v)
    if (std::isfinite(x)) sum += (x - mean) * (x - mean);
  return std::sqrt(sum / n);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_pose_smoothing_figure OUT.png\n");
    return 2;
  }
  constexpr int kFrames = 200;
  const testing::PoseSweep sweep = testing::RenderPoseSweep(kFrames);
  PoseFilter filter;
  const double nan = std::nan("");
  // The tilt error (the rotation error's component about the camera's x,
  // degrees) and the depth error (% of the distance), each frame's own and
  // filtered.
  std::vector<double> raw_tilt(kFrames, nan), tilt(kFrames, nan), raw_depth(kFrames, nan),
      depth(kFrames, nan);
  for (int f = 0; f < kFrames; ++f) {
    if (!sweep.found[f]) continue;
    const TagPose& pose = sweep.seen[f];
    const FilteredPose out =
        filter.Update(f / testing::kPoseSweepFps, pose.rvec, pose.tvec, pose.covariance);
    const double z = sweep.translation[f][2];
    raw_tilt[f] = testing::RotationError(pose.rvec, sweep.rotation[f])[0] * 180 / kPi;
    raw_depth[f] = 100 * (pose.tvec[2] - z) / z;
    tilt[f] = testing::RotationError(out.rvec, sweep.rotation[f])[0] * 180 / kPi;
    depth[f] = 100 * (out.tvec[2] - z) / z;
  }
  cv::Mat canvas(430, 900, CV_8UC3, cv::Scalar(255, 255, 255));
  Plot(&canvas, {60, 40, 820, 160},
       "rotation error about the camera's x, degrees (grey: each frame, blue: --smooth)", raw_tilt,
       tilt, -3, 3);
  Plot(&canvas, {60, 250, 820, 160}, "depth error, % of the distance", raw_depth, depth, -1, 1);
  if (!cv::imwrite(argv[1], canvas)) {
    std::fprintf(stderr, "cannot write '%s'\n", argv[1]);
    return 1;
  }
  // The jitter from the second second on (the first: the filter settling),
  // as pose_filter_test measures it.
  const auto settled = [](const std::vector<double>& v) {
    return std::vector<double>(v.begin() + 30, v.end());
  };
  std::printf("from frame 30, jitter: tilt %.3f -> %.3f degrees, depth %.3f -> %.3f %%\n",
              Jitter(settled(raw_tilt)), Jitter(settled(tilt)), Jitter(settled(raw_depth)),
              Jitter(settled(depth)));
  return 0;
}
