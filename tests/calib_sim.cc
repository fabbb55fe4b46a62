#include "calib_sim.h"

#include <cmath>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

namespace chromatag::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Printed colour -> the camera's linear RGB under unit light, before the
// cast and the exposure.
cv::Vec3d CameraLinear(const Lab& printed, const SimCamera& camera) {
  const Rgb lin = XyzToLinearRgb(LabToXyz(printed));
  return camera.matrix * cv::Vec3d(lin.r, lin.g, lin.b);
}

// Linear-light camera image of a BGR 8-bit picture of sent colours.
cv::Mat PrintAndSee(const cv::Mat& sent_bgr, const SimPrinter& printer, const SimCamera& camera) {
  cv::Mat out(sent_bgr.size(), CV_32FC3);
  std::unordered_map<uint32_t, cv::Vec3f> cache;
  for (int y = 0; y < sent_bgr.rows; ++y) {
    const cv::Vec3b* in = sent_bgr.ptr<cv::Vec3b>(y);
    cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
    for (int x = 0; x < sent_bgr.cols; ++x) {
      const uint32_t key = (in[x][2] << 16) | (in[x][1] << 8) | in[x][0];
      auto it = cache.find(key);
      if (it == cache.end()) {
        const cv::Vec3d rgb =
            CameraLinear(printer.Print(Rgb8{in[x][2], in[x][1], in[x][0]}), camera);
        // Stored B, G, R like the picture.
        it = cache
                 .emplace(key, cv::Vec3f(static_cast<float>(rgb[2]), static_cast<float>(rgb[1]),
                                         static_cast<float>(rgb[0])))
                 .first;
      }
      o[x] = it->second;
    }
  }
  return out;
}

// Cast, exposure, blur, tone curve, noise, 8 bits.
cv::Mat Develop(cv::Mat linear_bgr, const SimCamera& camera) {
  const cv::Scalar gains(camera.gains[2] * camera.exposure, camera.gains[1] * camera.exposure,
                         camera.gains[0] * camera.exposure);
  cv::multiply(linear_bgr, gains, linear_bgr);
  if (camera.blur_sigma_px > 0)
    cv::GaussianBlur(linear_bgr, linear_bgr, cv::Size(), camera.blur_sigma_px);
  cv::Mat noise(linear_bgr.size(), CV_32FC3);
  cv::RNG rng(camera.seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, camera.noise_sigma);
  cv::Mat out(linear_bgr.size(), CV_8UC3);
  for (int y = 0; y < linear_bgr.rows; ++y) {
    const cv::Vec3f* in = linear_bgr.ptr<cv::Vec3f>(y);
    const cv::Vec3f* n = noise.ptr<cv::Vec3f>(y);
    cv::Vec3b* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < linear_bgr.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double v = 255.0 * camera.Encode(std::clamp<double>(in[x][c], 0.0, 1.0)) + n[x][c];
        o[x][c] = cv::saturate_cast<uint8_t>(std::lround(v));
      }
    }
  }
  return out;
}

}  // namespace

Lab SimPrinter::Print(const Rgb8& sent) const {
  auto gain = [&](uint8_t v) { return 1.0 - std::pow(1.0 - v / 255.0, 1.0 / (1.0 + dot_gain)); };
  const Lab lab = SrgbToLab(Rgb{gain(sent.r), gain(sent.g), gain(sent.b)});
  const double chroma = std::hypot(lab.a, lab.b) * chroma_scale;
  const double hue = std::atan2(lab.b, lab.a) + hue_shift_deg * kPi / 180.0;
  return Lab{black_l + (100.0 - black_l) * lab.L / 100.0, chroma * std::cos(hue),
             chroma * std::sin(hue)};
}

double SimCamera::Encode(double linear) const {
  return gamma > 0 ? std::pow(std::max(linear, 0.0), 1.0 / gamma) : LinearToSrgb(linear);
}

Lab CameraReferredTruth(const Lab& printed, const SimCamera& camera) {
  auto seen = [&](const Lab& lab) {
    const cv::Vec3d lin = CameraLinear(lab, camera);
    Rgb out;
    double* channels[3] = {&out.r, &out.g, &out.b};
    for (int c = 0; c < 3; ++c) {
      const double v = std::clamp(lin[c] * camera.gains[c] * camera.exposure, 0.0, 1.0);
      *channels[c] = SrgbToLinear(camera.Encode(v));
    }
    return out;
  };
  const Rgb colour = seen(printed), white = seen(Lab{100, 0, 0});
  return XyzToLab(LinearRgbToXyz({colour.r / white.r, colour.g / white.g, colour.b / white.b}));
}

cv::Mat RenderSheetPhoto(const CalibSheetLayout& layout, const SimPrinter& printer,
                         const SimCamera& camera, double page_px_per_mm) {
  const cv::Mat page = RasterizeCalibPage(layout, page_px_per_mm);
  cv::Mat linear = PrintAndSee(page, printer, camera);
  // Uneven light: brightest off-centre (a lamp to the upper left), falling
  // to 1 - falloff at the far corner; not a quadratic, so the sampler's
  // white fit is only an approximation of it.
  for (int y = 0; y < linear.rows; ++y) {
    cv::Vec3f* row = linear.ptr<cv::Vec3f>(y);
    for (int x = 0; x < linear.cols; ++x) {
      const double u = static_cast<double>(x) / linear.cols - 0.35;
      const double v = static_cast<double>(y) / linear.rows - 0.3;
      const double light = 1.0 - camera.falloff * (1.0 - std::exp(-(u * u + v * v) / 0.5)) / 0.55;
      row[x] *= static_cast<float>(light);
    }
  }
  const double downscale =
      page.rows / cv::norm(camera.page_corners_px[3] - camera.page_corners_px[0]);
  if (downscale > 1.0) cv::GaussianBlur(linear, linear, cv::Size(), 0.45 * downscale);
  const cv::Point2f src[4] = {{-0.5f, -0.5f},
                              {page.cols - 0.5f, -0.5f},
                              {page.cols - 0.5f, page.rows - 0.5f},
                              {-0.5f, page.rows - 0.5f}};
  cv::Point2f dst[4];
  for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(camera.page_corners_px[i]);
  const cv::Mat h = cv::getPerspectiveTransform(src, dst);
  cv::Mat photo;
  // A dark grey table under the sheet.
  cv::warpPerspective(linear, photo, h, cv::Size(camera.width, camera.height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0.04, 0.045, 0.05));
  return Develop(photo, camera);
}

cv::Mat RenderPrintedTag(const TagFamily& family, int id, const TagColors& sent,
                         const SimPrinter& printer, const SimCamera& camera, double cell_px,
                         int width, int height) {
  const RgbImage tag = RasterizeTag(family, id, sent, cell_px);
  cv::Mat bgr(tag.height, tag.width, CV_8UC3);
  for (int y = 0; y < tag.height; ++y) {
    for (int x = 0; x < tag.width; ++x) {
      const uint8_t* p = tag.At(x, y);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);
    }
  }
  const cv::Mat linear_tag = PrintAndSee(bgr, printer, camera);
  cv::Mat scene(height, width, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3));
  const int x0 = (width - tag.width) / 2, y0 = (height - tag.height) / 2;
  linear_tag.copyTo(scene(cv::Rect(x0, y0, tag.width, tag.height)));
  return Develop(scene, camera);
}

}  // namespace chromatag::testing
