// The camera set: frames as hard as real cameras make them. See
// dataset.h for the list of conditions; the constants below fix their ranges.
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/bench/cast.h"
#include "chromatag/families/color.h"
#include "dataset_impl.h"

namespace chromatag::bench {
namespace {

// Decorrelates the camera set's frames from the classic set's of the same seed.
constexpr uint64_t kCameraSalt = 0xC0FFEE5EEDull;

// Light on the card: exposure times light level, 1 for paper white at the
// encoding's white; dim rooms and short exposures give 0.3.
constexpr double kMinExposure = 0.3, kMaxExposure = 1.5;
constexpr double kMaxGradient = 1.6;  // Brightest over darkest light on the card.
constexpr double kMinToneGamma = 0.75, kMaxToneGamma = 1.35;
constexpr double kMaxBlurSigma = 1.5;  // Pixels.
constexpr double kMotionShare = 0.25;  // Frames with motion blur of 1-5 px.
// Shot noise: sigma^2 = v * k, with k such that linear mid-grey (0.18) has
// this signal-to-noise ratio; read noise sigma in linear units.
constexpr double kMidGrey = 0.18;
constexpr double kMinSnr = 30.0, kMaxSnr = 80.0;
constexpr double kMinReadNoise = 0.002, kMaxReadNoise = 0.01;
constexpr double kBayerShare = 1.0 / 3.0;  // Half bilinear, half edge-aware.
constexpr double kJpegShare = 0.4;
constexpr int kMinJpegQuality = 60, kMaxJpegQuality = 95;
constexpr double kOneCellQuietShare = 0.4;  // The rest have 2 cells.
// Texture sampling: enough pixels per cell that a texel is no larger than a
// supersampled pixel, up to this (the largest tags are magnified a little).
constexpr int kMaxPixelsPerCell = 48;
constexpr int kEncodeSteps = 16384;  // Linear [0, 1] to 8 bits.

// Everything drawn for a frame besides the geometry. Every value is drawn
// whether it is used or not, so that a frame's other conditions do not depend
// on, say, whether it shakes.
void DrawConditions(Rng& rng, CameraPlan* plan) {
  FrameTruth* truth = &plan->truth;
  plan->cast = DrawFrameCast(rng.Bits());
  truth->mixed_light = plan->cast.mixed;
  truth->exposure = rng.Uniform(kMinExposure, kMaxExposure);
  truth->gradient = rng.Uniform(1.0, kMaxGradient);
  plan->gradient_angle = rng.Uniform(0.0, 2 * kPi);
  truth->tone_gamma = rng.Uniform(kMinToneGamma, kMaxToneGamma);
  truth->print = static_cast<PrintKind>(rng.Index(kNumPrintKinds));
  truth->blur_sigma_px = rng.Uniform(0.0, kMaxBlurSigma);
  const bool shake = rng.Uniform() < kMotionShare;
  const double length = rng.Uniform(1.0, 5.0);
  plan->motion_angle = rng.Uniform(0.0, kPi);
  truth->motion_blur_px = shake ? length : 0.0;
  truth->shot_snr = rng.Uniform(kMinSnr, kMaxSnr);
  truth->read_noise = rng.Uniform(kMinReadNoise, kMaxReadNoise);
  const bool bayer = rng.Uniform() < kBayerShare;
  const bool edge_aware = rng.Uniform() < 0.5;
  truth->bayer = !bayer       ? BayerMode::kNone
                 : edge_aware ? BayerMode::kEdgeAware
                              : BayerMode::kBilinear;
  const bool jpeg = rng.Uniform() < kJpegShare;
  const int quality = kMinJpegQuality + rng.Index(kMaxJpegQuality - kMinJpegQuality + 1);
  truth->jpeg_quality = jpeg ? quality : 0;
  plan->noise_seed = rng.Bits();
}

// The card's cells, one pixel each, as 8-bit RGB: the ChromaTag drawn by the
// generator (whole cells fall on whole pixels), the AprilTag from
// libapriltag's picture padded to the same quiet zone.
cv::Mat CardCells(const TagFamily& family, int id, const TagColors& colors,
                  const cv::Mat& april_picture, const SheetLayout& layout) {
  TagDrawOptions draw;
  draw.quiet_zone_cells = layout.quiet_cells;
  const RgbImage chroma = RasterizeTag(family, id, colors, 1.0, draw);
  const int n = layout.tag_cells();
  CV_Assert(chroma.width == n && chroma.height == n);
  cv::Mat cells(n, 2 * n, CV_8UC3);
  cv::Mat(n, n, CV_8UC3, const_cast<uint8_t*>(chroma.pixels.data()))
      .copyTo(cells(cv::Rect(0, 0, n, n)));
  const Rgb8 black = ToRgb8(colors[Shade::kBlack]), white = ToRgb8(colors[Shade::kWhite]);
  const int pad = (n - april_picture.cols) / 2;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const int py = y - pad, px = x - pad;
      const bool inside = py >= 0 && px >= 0 && py < april_picture.rows && px < april_picture.cols;
      const Rgb8& c = !inside || april_picture.at<uint8_t>(py, px) ? white : black;
      cells.at<cv::Vec3b>(y, n + x) = {c.r, c.g, c.b};
    }
  }
  return cells;
}

// Cells to a premultiplied linear BGRA texture with `ppc` pixels per cell.
cv::Mat CardTexture(const cv::Mat& cells_rgb, int ppc, const std::vector<float>& srgb_to_linear) {
  cv::Mat cells(cells_rgb.size(), CV_32FC4);
  for (int y = 0; y < cells.rows; ++y) {
    for (int x = 0; x < cells.cols; ++x) {
      const cv::Vec3b p = cells_rgb.at<cv::Vec3b>(y, x);
      cells.at<cv::Vec4f>(y, x) = {srgb_to_linear[p[2]], srgb_to_linear[p[1]], srgb_to_linear[p[0]],
                                   1.0f};
    }
  }
  cv::Mat texture;
  cv::resize(cells, texture, cv::Size(), ppc, ppc, cv::INTER_NEAREST);
  return texture;
}

// Composites the warped card over `linear` in its region of interest, the
// light changing linearly across the card (in the card's own plane) by
// `gradient` from its darkest to its brightest corner, 1 on average.
void Composite(const cv::Mat& sheet, const cv::Rect& roi, const Camera& camera,
               const SheetLayout& layout, double gradient, double angle, cv::Mat* linear) {
  const cv::Matx33d sheet_from_image = camera.ImageFromSheet().inv();
  const double dx = std::cos(angle), dy = std::sin(angle);
  const double reach = layout.half_x() * std::abs(dx) + layout.half_y() * std::abs(dy);
  const double slope = (gradient - 1.0) / (gradient + 1.0) / reach;
  cv::Mat target = (*linear)(roi);
  for (int y = 0; y < roi.height; ++y) {
    const cv::Vec4f* s = sheet.ptr<cv::Vec4f>(y);
    cv::Vec3f* t = target.ptr<cv::Vec3f>(y);
    for (int x = 0; x < roi.width; ++x) {
      if (s[x][3] <= 0.0f) continue;
      const cv::Vec3d p = sheet_from_image * cv::Vec3d(x + roi.x, y + roi.y, 1.0);
      const double u = p[0] / p[2], v = p[1] / p[2];
      const float light = static_cast<float>(1.0 + slope * (u * dx + v * dy));
      const float keep = 1.0f - s[x][3];
      for (int c = 0; c < 3; ++c) t[x][c] = light * s[x][c] + keep * t[x][c];
    }
  }
}

// Shot noise (variance proportional to the signal) and read noise, in linear
// light, then the sensor's clipping.
void AddSensorNoise(const FrameTruth& truth, uint64_t seed, cv::Mat* linear) {
  cv::Mat unit(linear->size(), CV_32FC3);
  cv::RNG rng(seed);
  rng.fill(unit, cv::RNG::NORMAL, 0.0, 1.0);
  const float k = static_cast<float>(kMidGrey / (truth.shot_snr * truth.shot_snr));
  const float read2 = static_cast<float>(truth.read_noise * truth.read_noise);
  for (int y = 0; y < linear->rows; ++y) {
    cv::Vec3f* v = linear->ptr<cv::Vec3f>(y);
    const cv::Vec3f* n = unit.ptr<cv::Vec3f>(y);
    for (int x = 0; x < linear->cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float signal = std::max(v[x][c], 0.0f);
        v[x][c] = std::clamp(signal + std::sqrt(k * signal + read2) * n[x][c], 0.0f, 1.0f);
      }
    }
  }
}

// An RGGB sensor: keeps one channel per pixel on 16-bit linear data and lets
// OpenCV demosaic it. OpenCV names Bayer patterns by the second row's second
// and third pixels, so an RGGB sensor is its "BayerBG".
void MosaicAndDemosaic(BayerMode mode, cv::Mat* linear) {
  cv::Mat raw(linear->size(), CV_16UC1);
  for (int y = 0; y < raw.rows; ++y) {
    const cv::Vec3f* in = linear->ptr<cv::Vec3f>(y);
    uint16_t* out = raw.ptr<uint16_t>(y);
    for (int x = 0; x < raw.cols; ++x) {
      // BGR channel indices: R on even rows and columns, B on odd ones.
      const int c = (y % 2 == 0) ? (x % 2 == 0 ? 2 : 1) : (x % 2 == 0 ? 1 : 0);
      out[x] = static_cast<uint16_t>(std::lround(std::clamp(in[x][c], 0.0f, 1.0f) * 65535.0f));
    }
  }
  cv::Mat bgr16;
  cv::cvtColor(raw, bgr16,
               mode == BayerMode::kEdgeAware ? cv::COLOR_BayerBG2BGR_EA : cv::COLOR_BayerBG2BGR);
  bgr16.convertTo(*linear, CV_32FC3, 1.0 / 65535.0);
}

// sRGB encoding, the camera's tone curve (v^gamma on the encoded value) and
// 8 bits.
cv::Mat Encode(const cv::Mat& linear, double tone_gamma) {
  std::vector<uint8_t> table(kEncodeSteps + 1);
  for (int i = 0; i <= kEncodeSteps; ++i) {
    const double encoded =
        std::pow(LinearToSrgb(static_cast<double>(i) / kEncodeSteps), tone_gamma);
    table[i] = static_cast<uint8_t>(std::lround(std::clamp(encoded, 0.0, 1.0) * 255));
  }
  return EncodeThrough(linear, table);
}

// Light, optics, sensor, camera processing and compression, in that order.
cv::Mat Develop(cv::Mat linear, const CameraPlan& plan) {
  const FrameTruth& truth = plan.truth;
  // The white balance's gains, before the sensor clips (a gain above 1 can
  // clip white, as in a camera).
  if (plan.cast.mixed) {
    cv::multiply(linear, plan.cast.GainMap(linear.size()), linear, truth.exposure);
  } else {
    const CastGains& g = plan.cast.first;
    cv::multiply(linear, cv::Scalar(g.blue, 1.0, g.red) * truth.exposure, linear);
  }
  if (truth.blur_sigma_px >= 0.05)
    cv::GaussianBlur(linear, linear, cv::Size(), truth.blur_sigma_px);
  if (truth.motion_blur_px > 0) {
    cv::filter2D(linear, linear, -1, MotionKernel(truth.motion_blur_px, plan.motion_angle));
  }
  AddSensorNoise(truth, plan.noise_seed, &linear);
  if (truth.bayer != BayerMode::kNone) MosaicAndDemosaic(truth.bayer, &linear);
  cv::Mat bgr = Encode(linear, truth.tone_gamma);
  if (truth.jpeg_quality == 0) return bgr;
  // OpenCV's default JPEG subsampling is 4:2:0, as most cameras write.
  std::vector<uchar> bytes;
  cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, truth.jpeg_quality});
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

}  // namespace

bool Dataset::Impl::LoadCameraFamilies(std::string* error) {
  const char* names[2] = {"16h5", "36h11"};
  apriltag_family_t* april[2] = {tag16h5_create(), tag36h11_create()};
  bool ok = true;
  for (int f = 0; f < 2 && ok; ++f) {
    CameraFamily& out = camera_families[f];
    out.family = TagFamily::Load(names[f], error);
    ok = out.family != nullptr;
    if (!ok) break;
    out.april_pictures.resize(out.family->num_apriltag_ids());
    for (int id : out.family->kept_ids()) out.april_pictures[id] = AprilTagPicture(april[f], id);
  }
  tag16h5_destroy(april[0]);
  tag36h11_destroy(april[1]);
  return ok;
}

CameraPlan Dataset::Impl::PlanCamera(int index) const {
  const DatasetOptions& o = options;
  Rng rng(FrameSeed(o.seed ^ kCameraSalt, index));
  CameraPlan plan;
  FrameTruth& truth = plan.truth;
  truth.index = index;
  truth.kind = DatasetKind::kCamera;
  truth.has_tags = rng.Uniform() >= o.tag_free_share;
  plan.family = &camera_families[index % 2];  // Half each, alternating.
  const std::vector<int>& kept = plan.family->family->kept_ids();
  plan.id = kept[rng.Index(static_cast<int>(kept.size()))];
  plan.layout.square_cells = plan.family->family->black_square_cells();
  plan.layout.quiet_cells = rng.Uniform() < kOneCellQuietShare ? 1 : 2;
  plan.photo = rng.Index(static_cast<int>(photos.size()));
  truth.photo = photo_names[plan.photo];
  plan.background_seed = rng.Bits();
  const PathPoint path = CameraPath(o, index, rng);
  DrawConditions(rng, &plan);
  if (truth.has_tags) {
    plan.camera = PlaceCamera(o, plan.layout, path, rng);
    truth.family = plan.family->family->name();
    truth.quiet_zone_cells = plan.layout.quiet_cells;
    truth.chromatag = TagTruthAt(plan.camera, plan.layout.chroma_centre_x(), plan.id);
    truth.apriltag = TagTruthAt(plan.camera, plan.layout.april_centre_x(), plan.id);
    truth.chromatag.family = truth.apriltag.family = truth.family;
  } else {
    truth.print_chroma = 0.0;  // No card.
    truth.gradient = 1.0;
  }
  const cv::Size frame(o.width, o.height);
  const cv::Point2d centre = truth.has_tags
                                 ? plan.camera.Project(cv::Vec3d(0, 0, 0))
                                 : cv::Point2d((o.width - 1) / 2.0, (o.height - 1) / 2.0);
  const CastGains gains = plan.cast.At(centre, frame);
  truth.red_gain = gains.red;
  truth.blue_gain = gains.blue;
  truth.cast = CastKindName(CastKindOf(gains));
  truth.condition = truth.cast == std::string("neutral") && !truth.mixed_light
                        ? ColorCondition::kWhiteBalanced
                        : ColorCondition::kColorCast;
  return plan;
}

Frame Dataset::Impl::RenderCamera(int index) const {
  const CameraPlan plan = PlanCamera(index);
  Rng background_rng(plan.background_seed);
  cv::Mat linear = LinearBackground(plan.photo, background_rng);
  if (plan.truth.has_tags) {
    const int k = options.supersampling;
    const SheetFootprint footprint = Footprint(plan.camera, plan.layout, linear.size(), k);
    if (!footprint.roi.empty()) {
      const int ppc =
          std::clamp(static_cast<int>(std::ceil(footprint.needed_ppc)), 2, kMaxPixelsPerCell);
      const TagColors& colors = printed_colors[static_cast<int>(plan.truth.print)];
      const cv::Mat cells = CardCells(*plan.family->family, plan.id, colors,
                                      plan.family->april_pictures[plan.id], plan.layout);
      const cv::Mat sheet = WarpSheet(CardTexture(cells, ppc, srgb_to_linear), ppc, plan.camera,
                                      plan.layout, footprint.roi, k);
      Composite(sheet, footprint.roi, plan.camera, plan.layout, plan.truth.gradient,
                plan.gradient_angle, &linear);
    }
  }
  Frame frame;
  frame.truth = plan.truth;
  frame.bgr = Develop(std::move(linear), plan);
  return frame;
}

}  // namespace chromatag::bench
