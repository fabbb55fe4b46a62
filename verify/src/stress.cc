#include "chromatag/verify/stress.h"

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "chromatag/families/color.h"

namespace chromatag {
namespace {

constexpr double kFocalPx = 800.0;
constexpr int kRasterPixelsPerCell = 16;

// Projects a point of the tag plane (black-square units, centre at 0, x
// right, y down) seen from `distance` with the tag turned by tilt and roll.
cv::Point2f Project(double x, double y, const ViewParams& p, double distance, cv::Size frame) {
  const double roll = p.roll_deg * kPi / 180.0, tilt = p.tilt_deg * kPi / 180.0;
  const double xr = x * std::cos(roll) - y * std::sin(roll);
  const double yr = x * std::sin(roll) + y * std::cos(roll);
  const double yc = yr * std::cos(tilt);
  const double zc = distance + yr * std::sin(tilt);
  return {static_cast<float>(frame.width / 2.0 + kFocalPx * xr / zc),
          static_cast<float>(frame.height / 2.0 + kFocalPx * yc / zc)};
}

bool DecodedAs(const Detector& detector, const cv::Mat& frame, const TagFamily& family, int id) {
  const DetectionResult result = detector.Detect(frame, PixelOrder::kBgr);
  return result.detections.size() == 1 && result.detections[0].id == id &&
         result.detections[0].family == &family;
}

// What a camera does to the view: blur, a colour cast, a Bayer mosaic
// demosaiced, noise and JPEG, each when `params` asks for it.
void ApplyCamera(const ViewParams& params, cv::Mat* frame_bgr) {
  cv::Mat& frame = *frame_bgr;
  if (params.blur_sigma > 0.0) cv::GaussianBlur(frame, frame, cv::Size(), params.blur_sigma);
  if (params.gains != cv::Vec3d(1, 1, 1)) {
    cv::multiply(frame, cv::Scalar(params.gains[2], params.gains[1], params.gains[0]), frame);
  }
  if (params.bayer) {
    cv::Mat mosaic(frame.size(), CV_8UC1);
    for (int y = 0; y < frame.rows; ++y) {
      for (int x = 0; x < frame.cols; ++x) {
        // RGGB: R at even row/even column, B at odd/odd, G elsewhere.
        const int channel = (y % 2 == 0 && x % 2 == 0) ? 2 : (y % 2 == 1 && x % 2 == 1) ? 0 : 1;
        mosaic.at<uint8_t>(y, x) = frame.at<cv::Vec3b>(y, x)[channel];
      }
    }
    cv::cvtColor(mosaic, frame, cv::COLOR_BayerBG2BGR);  // OpenCV names RGGB "BG".
  }
  if (params.noise_sigma > 0.0) {
    cv::Mat noise(frame.size(), CV_16SC3);
    cv::theRNG().state = params.seed;
    cv::randn(noise, 0, params.noise_sigma);
    cv::Mat wide;
    frame.convertTo(wide, CV_16SC3);
    wide += noise;
    wide.convertTo(frame, CV_8UC3);
  }
  if (params.jpeg_quality > 0) {
    std::vector<uchar> bytes;
    cv::imencode(".jpg", frame, bytes, {cv::IMWRITE_JPEG_QUALITY, params.jpeg_quality});
    frame = cv::imdecode(bytes, cv::IMREAD_COLOR);
  }
}

// The tag as BGR pixels, kRasterPixelsPerCell a cell.
cv::Mat TagImage(const TagFamily& family, int id, const TagColors& colors,
                 const TagDrawOptions& draw) {
  const RgbImage raster = RasterizeTag(family, id, colors, kRasterPixelsPerCell, draw);
  cv::Mat tag_rgb(raster.height, raster.width, CV_8UC3, const_cast<uint8_t*>(raster.pixels.data()));
  cv::Mat tag;
  cv::cvtColor(tag_rgb, tag, cv::COLOR_RGB2BGR);
  return tag;
}

}  // namespace

cv::Mat RenderView(const TagFamily& family, int id, const TagColors& colors,
                   const ViewParams& params, std::array<cv::Point2d, 4>* corners) {
  TagDrawOptions draw;
  draw.quiet_zone_cells = 2;
  cv::Mat tag = TagImage(family, id, colors, draw);
  const int cells = family.black_square_cells();
  const double outer = static_cast<double>(OuterCells(family, draw)) / cells;  // In squares.
  const double distance = kFocalPx / params.size_px;  // Black square of side 1 at `distance`.
  const int side = static_cast<int>(std::ceil(params.size_px * outer * 1.6)) + 40;
  const cv::Size frame_size(std::max(side, 64), std::max(side, 64));
  // Shrink first so that the perspective warp samples without aliasing.
  const double scale = std::min(1.0, 1.5 * params.size_px / (kRasterPixelsPerCell * cells));
  if (scale < 1.0) cv::resize(tag, tag, cv::Size(), scale, scale, cv::INTER_AREA);
  const double h = outer / 2.0;
  const cv::Point2f source[4] = {{0, 0},
                                 {static_cast<float>(tag.cols), 0},
                                 {static_cast<float>(tag.cols), static_cast<float>(tag.rows)},
                                 {0, static_cast<float>(tag.rows)}};
  const cv::Point2f target[4] = {
      Project(-h, -h, params, distance, frame_size), Project(h, -h, params, distance, frame_size),
      Project(h, h, params, distance, frame_size), Project(-h, h, params, distance, frame_size)};
  // Pixel-edge coordinates to pixel-centre ones on both sides.
  cv::Matx33d to_centres(1, 0, -0.5, 0, 1, -0.5, 0, 0, 1), to_edges(1, 0, 0.5, 0, 1, 0.5, 0, 0, 1);
  const cv::Matx33d warp =
      to_centres * cv::Matx33d(cv::getPerspectiveTransform(source, target)) * to_edges;
  cv::Mat frame;
  cv::warpPerspective(tag, frame, warp, frame_size, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar(170, 175, 180));
  if (corners) {
    const double s[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
    for (int i = 0; i < 4; ++i) {
      const cv::Point2f p = Project(s[i][0], s[i][1], params, distance, frame_size);
      (*corners)[i] = {p.x - 0.5, p.y - 0.5};
    }
  }
  ApplyCamera(params, &frame);
  return frame;
}

TagStress StressTag(const TagFamily& family, int id, const TagColors& colors,
                    const Detector& detector, const StressOptions& options) {
  TagStress stress;
  stress.id = id;
  for (double size = options.largest_size_px; size >= options.smallest_size_px;
       size *= options.size_step) {
    ViewParams view;
    view.size_px = size;
    view.roll_deg = 7.0;  // Off the pixel grid.
    if (!DecodedAs(detector, RenderView(family, id, colors, view), family, id)) break;
    stress.smallest_size_px = size;
  }
  for (double tilt : options.tilts_deg) {
    ViewParams view;
    view.size_px = options.tilt_size_px;
    view.tilt_deg = tilt;
    view.roll_deg = 7.0;
    if (!DecodedAs(detector, RenderView(family, id, colors, view), family, id)) break;
    stress.largest_tilt_deg = tilt;
  }
  struct Named {
    std::string name;
    ViewParams view;
  };
  std::vector<Named> conditions(6);
  conditions[0].name = "blur 1.5 px";
  conditions[0].view.blur_sigma = 1.5;
  conditions[1].name = "noise 8 levels";
  conditions[1].view.noise_sigma = 8.0;
  conditions[2].name = "JPEG q40";
  conditions[2].view.jpeg_quality = 40;
  conditions[3].name = "warm cast";
  conditions[3].view.gains = {1.25, 1.0, 0.7};
  conditions[4].name = "cool cast";
  conditions[4].view.gains = {0.75, 1.0, 1.3};
  conditions[5].name = "Bayer";
  conditions[5].view.bayer = true;
  stress.all_conditions_decoded = true;
  for (auto& condition : conditions) {
    condition.view.size_px = options.condition_size_px;
    condition.view.roll_deg = 7.0;
    condition.view.seed = static_cast<uint64_t>(id) + 1;
    const bool decoded =
        DecodedAs(detector, RenderView(family, id, colors, condition.view), family, id);
    stress.conditions.push_back({condition.name, decoded});
    stress.all_conditions_decoded = stress.all_conditions_decoded && decoded;
  }
  return stress;
}

}  // namespace chromatag
