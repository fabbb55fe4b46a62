#include "synthetic_scene.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag::testing {
namespace {

cv::Matx33d Rotation(const cv::Vec3d& axis, double degrees) {
  cv::Matx33d r;
  cv::Rodrigues(cv::Vec3d(axis * (degrees * kPi / 180.0)), r);
  return r;
}

// Maps the tag plane (the black square is [-0.5, 0.5]^2, u right, v down on
// the upright tag) to scene pixels.
cv::Matx33d SceneFromTagPlane(const SceneTag& tag) {
  const double t = tag.tilt_axis_deg * kPi / 180.0;
  const cv::Matx33d r =
      Rotation({std::cos(t), std::sin(t), 0}, tag.tilt_deg) * Rotation({0, 0, 1}, tag.rotation_deg);
  const double z = tag.distance;
  const double f = tag.black_square_px * z;
  const cv::Matx33d k(f, 0, tag.centre.x, 0, f, tag.centre.y, 0, 0, 1);
  const cv::Matx33d rt(r(0, 0), r(0, 1), 0, r(1, 0), r(1, 1), 0, r(2, 0), r(2, 1), z);
  return k * rt;
}

cv::Point2d Apply(const cv::Matx33d& h, double x, double y) {
  const cv::Vec3d p = h * cv::Vec3d(x, y, 1);
  return {p[0] / p[2], p[1] / p[2]};
}

cv::Mat Background(const SceneOptions& options) {
  cv::Mat bgr;
  if (!options.background.empty()) {
    cv::resize(options.background, bgr, cv::Size(options.width, options.height), 0, 0,
               cv::INTER_AREA);
    return bgr;
  }
  bgr.create(options.height, options.width, CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const int v = 150 + (60 * x) / std::max(1, bgr.cols) + (30 * y) / std::max(1, bgr.rows);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(v, v, v);
    }
  }
  return bgr;
}

float SrgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

float LinearToSrgb(float v) {
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
}

// SceneOptions::linear_camera: light, optics and sensor in linear values,
// then the camera's tone curve.
cv::Mat LinearCamera(const cv::Mat& bgr, const SceneOptions& options) {
  cv::Mat f;
  bgr.convertTo(f, CV_32FC3, 1.0 / 255);
  const cv::Vec3f gain(static_cast<float>(options.exposure * options.gain[2]),
                       static_cast<float>(options.exposure * options.gain[1]),
                       static_cast<float>(options.exposure * options.gain[0]));
  f.forEach<cv::Vec3f>([&](cv::Vec3f& p, const int*) {
    for (int c = 0; c < 3; ++c) p[c] = SrgbToLinear(p[c]) * gain[c];
  });
  if (options.blur_sigma > 0) cv::GaussianBlur(f, f, cv::Size(0, 0), options.blur_sigma);
  cv::RNG rng(options.seed);
  const float read = static_cast<float>(options.noise_sigma / 255.0);
  const float shot = static_cast<float>(options.shot_noise);
  auto noisy = [&](float v) {
    const float sigma = std::sqrt(read * read + shot * shot * std::max(v, 0.f));
    return std::clamp(v + static_cast<float>(rng.gaussian(sigma)), 0.f, 1.f);
  };
  if (options.demosaic == Demosaic::kNone) {
    for (int y = 0; y < f.rows; ++y) {
      for (int x = 0; x < f.cols; ++x) {
        cv::Vec3f& p = f.at<cv::Vec3f>(y, x);
        for (int c = 0; c < 3; ++c) p[c] = noisy(p[c]);
      }
    }
  } else {
    // RGGB: R at even rows and columns, B at odd ones (BGR channel indices).
    cv::Mat raw(f.size(), CV_16UC1);
    for (int y = 0; y < f.rows; ++y) {
      for (int x = 0; x < f.cols; ++x) {
        const int channel = (y % 2 == 0 && x % 2 == 0) ? 2 : (y % 2 == 1 && x % 2 == 1) ? 0 : 1;
        raw.at<uint16_t>(y, x) =
            static_cast<uint16_t>(std::lround(noisy(f.at<cv::Vec3f>(y, x)[channel]) * 65535.f));
      }
    }
    // OpenCV names Bayer patterns by the second row's first two pixels: an
    // RGGB sensor is its "BayerBG". Demosaiced on the linear raw values, as
    // a camera's processor does.
    cv::Mat demosaiced;
    cv::cvtColor(
        raw, demosaiced,
        options.demosaic == Demosaic::kBilinear ? cv::COLOR_BayerBG2BGR : cv::COLOR_BayerBG2BGR_EA);
    demosaiced.convertTo(f, CV_32FC3, 1.0 / 65535);
  }
  cv::Mat out(f.size(), CV_8UC3);
  for (int y = 0; y < f.rows; ++y) {
    for (int x = 0; x < f.cols; ++x) {
      const cv::Vec3f& p = f.at<cv::Vec3f>(y, x);
      for (int c = 0; c < 3; ++c)
        out.at<cv::Vec3b>(y, x)[c] =
            cv::saturate_cast<uint8_t>(255.f * std::pow(LinearToSrgb(std::clamp(p[c], 0.f, 1.f)),
                                                        static_cast<float>(options.tone_gamma)));
    }
  }
  return out;
}

}  // namespace

cv::Mat SrgbToLinearImage(const cv::Mat& bgr) {
  static const std::vector<float> to_linear = [] {
    std::vector<float> t(256);
    for (int i = 0; i < 256; ++i) t[i] = SrgbToLinear(i / 255.f);
    return t;
  }();
  cv::Mat linear(bgr.size(), CV_32FC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const uint8_t* in = bgr.ptr<uint8_t>(y);
    float* out = linear.ptr<float>(y);
    for (int i = 0; i < 3 * bgr.cols; ++i) out[i] = to_linear[in[i]];
  }
  return linear;
}

cv::Mat LinearToSrgbImage(const cv::Mat& linear) {
  cv::Mat bgr(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y) {
    const float* in = linear.ptr<float>(y);
    uint8_t* out = bgr.ptr<uint8_t>(y);
    for (int i = 0; i < 3 * linear.cols; ++i)
      out[i] = cv::saturate_cast<uint8_t>(255.f * LinearToSrgb(std::clamp(in[i], 0.f, 1.f)));
  }
  return bgr;
}

namespace {

cv::Mat AverageInLinearLight(const cv::Mat& hi, cv::Size size) {
  cv::Mat small;
  cv::resize(SrgbToLinearImage(hi), small, size, 0, 0, cv::INTER_AREA);
  return LinearToSrgbImage(small);
}

}  // namespace

void ApplyCamera(const SceneOptions& options, cv::Mat* bgr) {
  if (options.linear_camera) {
    *bgr = LinearCamera(*bgr, options);
  } else if (options.blur_sigma > 0 && options.blur_in_linear_light) {
    // As a lens does: decode the sRGB curve, blur, encode again.
    cv::Mat f;
    bgr->convertTo(f, CV_32FC3, 1.0 / 255);
    f.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
      for (int c = 0; c < 3; ++c)
        p[c] = p[c] <= 0.04045f ? p[c] / 12.92f : std::pow((p[c] + 0.055f) / 1.055f, 2.4f);
    });
    cv::GaussianBlur(f, f, cv::Size(0, 0), options.blur_sigma);
    f.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
      for (int c = 0; c < 3; ++c)
        p[c] = 255.f *
               (p[c] <= 0.0031308f ? 12.92f * p[c] : 1.055f * std::pow(p[c], 1 / 2.4f) - 0.055f);
    });
    f.convertTo(*bgr, CV_8UC3);
  } else if (options.blur_sigma > 0) {
    cv::GaussianBlur(*bgr, *bgr, cv::Size(0, 0), options.blur_sigma);
  }
  if (!options.linear_camera && (options.gain != cv::Vec3d(1, 1, 1) || options.noise_sigma > 0)) {
    cv::Mat f;
    bgr->convertTo(f, CV_32FC3);
    cv::multiply(f, cv::Scalar(options.gain[2], options.gain[1], options.gain[0]), f);
    if (options.noise_sigma > 0) {
      cv::Mat noise(f.size(), CV_32FC3);
      cv::RNG rng(options.seed);
      rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
      f += noise;
    }
    f.convertTo(*bgr, CV_8UC3);  // Rounds and saturates.
  }
  if (options.jpeg_quality > 0) {
    std::vector<uchar> bytes;
    cv::imencode(".jpg", *bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality});
    *bgr = cv::imdecode(bytes, cv::IMREAD_COLOR);
  }
}

DetectorOptions PoseOptionsFor(const SceneTag& tag, const cv::Point2d& principal) {
  DetectorOptions options;
  CameraIntrinsics camera;
  camera.fx = camera.fy = tag.black_square_px * tag.distance;  // As RenderScene places it.
  camera.cx = principal.x;
  camera.cy = principal.y;
  options.camera = camera;
  options.tag_size = 1.0;
  return options;
}

Scene RenderScene(const std::vector<SceneTag>& tags, const SceneOptions& options) {
  double smallest = 1e300;
  for (const auto& tag : tags) smallest = std::min(smallest, tag.black_square_px);
  // Supersampling: enough that small tags' edges are averaged properly.
  const int s = smallest < 100 ? 4 : 2;
  const cv::Matx33d hi_from_scene(s, 0, (s - 1) / 2.0, 0, s, (s - 1) / 2.0, 0, 0, 1);

  cv::Mat hi;
  cv::resize(Background(options), hi, cv::Size(options.width * s, options.height * s), 0, 0,
             cv::INTER_NEAREST);
  Scene scene;
  for (const SceneTag& tag : tags) {
    std::string error;
    auto family = TagFamily::Load(tag.family, &error);
    if (!family) throw std::runtime_error(error);
    auto palette = BuiltinPalette(tag.palette, &error);
    if (!palette) throw std::runtime_error(error);
    Palette printed = *palette;
    for (Shade shade : {Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0}) {
      printed[shade].a *= tag.print_chroma;
      printed[shade].b *= tag.print_chroma;
    }
    TagColors colors = TagColors::FromPalette(printed);
    if (tag.swap_shades) {
      std::swap(colors[Shade::kRed1], colors[Shade::kRed0]);
      std::swap(colors[Shade::kGreen1], colors[Shade::kGreen0]);
    }
    if (tag.reds_alike) colors[Shade::kRed1] = colors[Shade::kRed0];
    TagDrawOptions draw;
    draw.quiet_zone_cells = tag.quiet_zone_cells;
    const int cells = family->black_square_cells();
    // About 1.5 source pixels per supersampled scene pixel.
    const double ppc = std::ceil(1.5 * tag.black_square_px * s / cells);
    const RgbImage image = RasterizeTag(*family, tag.id, colors, ppc, draw);
    const double edge = (OuterCells(*family, draw) - cells) / 2 * ppc;
    // Rendered pixel centres -> tag plane.
    const double side = cells * ppc;
    const cv::Matx33d plane_from_render(1 / side, 0, -(edge - 0.5) / side - 0.5, 0, 1 / side,
                                        -(edge - 0.5) / side - 0.5, 0, 0, 1);
    const cv::Matx33d scene_from_plane = SceneFromTagPlane(tag);
    cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.pixels.data()));
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    // Warp only into the box the tag covers: whole-canvas warps made scenes
    // with many tags slow.
    const cv::Matx33d hi_from_render = hi_from_scene * scene_from_plane * plane_from_render;
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (int i = 0; i < 4; ++i) {
      const cv::Point2d p =
          Apply(hi_from_render, (i % 3 ? image.width : 0) - 0.5, (i / 2 ? image.height : 0) - 0.5);
      x0 = std::min(x0, p.x);
      y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x);
      y1 = std::max(y1, p.y);
    }
    const cv::Rect roi =
        cv::Rect(
            cv::Point(static_cast<int>(std::floor(x0)) - 2, static_cast<int>(std::floor(y0)) - 2),
            cv::Point(static_cast<int>(std::ceil(x1)) + 3, static_cast<int>(std::ceil(y1)) + 3)) &
        cv::Rect(0, 0, hi.cols, hi.rows);
    if (!roi.empty()) {
      const cv::Matx33d shift(1, 0, -roi.x, 0, 1, -roi.y, 0, 0, 1);
      cv::Mat target = hi(roi);
      cv::warpPerspective(bgr, target, cv::Mat(shift * hi_from_render), target.size(),
                          cv::INTER_LINEAR, cv::BORDER_TRANSPARENT);
    }
    TagTruth truth;
    truth.family = family->name();
    truth.id = tag.id;
    const double corners[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
    for (int i = 0; i < 4; ++i)
      truth.corners[i] = Apply(scene_from_plane, corners[i][0], corners[i][1]);
    scene.truth.push_back(truth);
  }
  // Each pixel collects the light on its area, as a sensor does: averaged
  // in linear light, then encoded again.
  scene.bgr = AverageInLinearLight(hi, cv::Size(options.width, options.height));
  ApplyCamera(options, &scene.bgr);
  return scene;
}

double MaxCornerError(const std::array<cv::Point2d, 4>& a, const std::array<cv::Point2d, 4>& b) {
  double worst = 0;
  for (int i = 0; i < 4; ++i) worst = std::max(worst, cv::norm(a[i] - b[i]));
  return worst;
}

std::array<cv::Point2d, 4> InnerCorners(const TagTruth& truth, int cells, int inset_cells) {
  const std::vector<cv::Point2f> unit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<cv::Point2f> corners(truth.corners.begin(), truth.corners.end());
  const cv::Matx33d h(cv::getPerspectiveTransform(unit, corners));
  const double in = static_cast<double>(inset_cells) / cells;
  const double square[4][2] = {{in, in}, {1 - in, in}, {1 - in, 1 - in}, {in, 1 - in}};
  std::array<cv::Point2d, 4> out;
  for (int i = 0; i < 4; ++i) {
    const cv::Vec3d p = h * cv::Vec3d(square[i][0], square[i][1], 1.0);
    out[i] = {p[0] / p[2], p[1] / p[2]};
  }
  return out;
}

}  // namespace chromatag::testing
