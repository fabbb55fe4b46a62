#include "calib_sim.h"

#include <cmath>
#include <functional>
#include <unordered_map>

#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"

namespace chromatag::testing {
namespace {

// The scanner's lid, seen through the glass around the paper: linear light
// relative to the paper's white.
constexpr double kLidWhite = 0.85;

// Printed colour -> the camera's linear RGB under unit light, before the
// cast and the exposure.
cv::Vec3d CameraLinear(const Lab& printed, const SimCamera& camera) {
  const Rgb lin = XyzToLinearRgb(LabToXyz(printed));
  return camera.matrix * cv::Vec3d(lin.r, lin.g, lin.b);
}

// Linear light of a BGR 8-bit picture of sent colours once printed by
// `print` and seen through `see` (printed CIELAB -> linear R, G, B), B, G, R
// like the picture. Each colour is printed and seen once.
cv::Mat PrintAndSee(const cv::Mat& sent_bgr, const PrintFn& print,
                    const std::function<cv::Vec3d(const Lab&)>& see) {
  cv::Mat out(sent_bgr.size(), CV_32FC3);
  std::unordered_map<uint32_t, cv::Vec3f> cache;
  for (int y = 0; y < sent_bgr.rows; ++y) {
    const cv::Vec3b* in = sent_bgr.ptr<cv::Vec3b>(y);
    cv::Vec3f* o = out.ptr<cv::Vec3f>(y);
    for (int x = 0; x < sent_bgr.cols; ++x) {
      const uint32_t key = (in[x][2] << 16) | (in[x][1] << 8) | in[x][0];
      auto it = cache.find(key);
      if (it == cache.end()) {
        const cv::Vec3d rgb = see(print(Rgb8{in[x][2], in[x][1], in[x][0]}));
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

cv::Mat PrintAndSee(const cv::Mat& sent_bgr, const PrintFn& print, const SimCamera& camera) {
  return PrintAndSee(sent_bgr, print, [&](const Lab& lab) { return CameraLinear(lab, camera); });
}

// The printed page's content scaled about the page's centre, in place; the
// paper it no longer covers is `paper` (B, G, R linear light).
void ApplyPrintGeometry(const PrintGeometry& geometry, const cv::Vec3d& paper,
                        cv::Mat& linear_page) {
  if (geometry.scale_x == 1.0 && geometry.scale_y == 1.0) return;
  // Pixel centres at integers: the page's centre is at ((cols - 1) / 2, ...).
  const double cx = 0.5 * (linear_page.cols - 1), cy = 0.5 * (linear_page.rows - 1);
  const cv::Matx23d paper_from_content(geometry.scale_x, 0, (1 - geometry.scale_x) * cx,  //
                                       0, geometry.scale_y, (1 - geometry.scale_y) * cy);
  cv::Mat scaled;
  cv::warpAffine(linear_page, scaled, paper_from_content, linear_page.size(), cv::INTER_LINEAR,
                 cv::BORDER_CONSTANT, cv::Scalar(paper[0], paper[1], paper[2]));
  linear_page = scaled;
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
  return PrintAndPhotograph(
      RasterizeCalibPage(layout, page_px_per_mm), page_px_per_mm,
      [&](const Rgb8& sent) { return printer.Print(sent); }, PrintGeometry{}, camera);
}

cv::Mat PrintAndPhotograph(const cv::Mat& page_bgr, double page_px_per_mm, const PrintFn& print,
                           const PrintGeometry& geometry, const SimCamera& camera) {
  (void)page_px_per_mm;  // The camera's page_corners_px say where the page lands.
  auto see = [&](const Lab& lab) { return CameraLinear(lab, camera); };
  cv::Mat linear = PrintAndSee(page_bgr, print, see);
  const cv::Vec3d paper_rgb = see(Lab{100, 0, 0});
  ApplyPrintGeometry(geometry, {paper_rgb[2], paper_rgb[1], paper_rgb[0]}, linear);
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
      linear.rows / cv::norm(camera.page_corners_px[3] - camera.page_corners_px[0]);
  if (downscale > 1.0) cv::GaussianBlur(linear, linear, cv::Size(), 0.45 * downscale);
  const cv::Point2f src[4] = {{-0.5f, -0.5f},
                              {linear.cols - 0.5f, -0.5f},
                              {linear.cols - 0.5f, linear.rows - 0.5f},
                              {-0.5f, linear.rows - 0.5f}};
  cv::Point2f dst[4];
  for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(camera.page_corners_px[i]);
  const cv::Mat h = cv::getPerspectiveTransform(src, dst);
  cv::Mat photo;
  // A dark grey table under the sheet.
  cv::warpPerspective(linear, photo, h, cv::Size(camera.width, camera.height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0.04, 0.045, 0.05));
  return Develop(photo, camera);
}

cv::Point2d ScanPixelOfPagePoint(const cv::Point2d& page_mm, const cv::Size2d& page_size_mm,
                                 const PrintGeometry& geometry, const SimScanner& scanner) {
  const cv::Point2d centre(0.5 * page_size_mm.width, 0.5 * page_size_mm.height);
  const cv::Point2d on_paper(centre.x + geometry.scale_x * (page_mm.x - centre.x),
                             centre.y + geometry.scale_y * (page_mm.y - centre.y));
  const double angle = scanner.rotation_deg * kPi / 180.0;
  const double c = std::cos(angle), s = std::sin(angle);
  // Counter-clockwise as seen in the scan, whose y axis points down.
  const cv::Point2d on_glass(c * on_paper.x + s * on_paper.y + scanner.offset_mm.x,
                             -s * on_paper.x + c * on_paper.y + scanner.offset_mm.y);
  const double px_per_mm = scanner.dpi / 25.4;
  return on_glass * px_per_mm - cv::Point2d(0.5, 0.5);
}

cv::Mat PrintAndScan(const cv::Mat& page_bgr, double page_px_per_mm, const PrintFn& print,
                     const PrintGeometry& geometry, const SimScanner& scanner) {
  // A colorimetric scanner: linear sRGB of the print, the paper at 1.
  auto see = [](const Lab& lab) {
    const Rgb lin = XyzToLinearRgb(LabToXyz(lab));
    return cv::Vec3d(lin.r, lin.g, lin.b);
  };
  cv::Mat linear = PrintAndSee(page_bgr, print, see);
  ApplyPrintGeometry(geometry, {1.0, 1.0, 1.0}, linear);
  const double scan_px_per_mm = scanner.dpi / 25.4;
  const double downscale = page_px_per_mm / scan_px_per_mm;
  if (downscale > 1.0) cv::GaussianBlur(linear, linear, cv::Size(), 0.45 * downscale);
  // Page pixel (u, v) is at page position ((u, v) + 0.5) / page_px_per_mm;
  // ScanPixelOfPagePoint (with the scale already applied) is affine in it.
  const cv::Size2d page_size_mm(linear.cols / page_px_per_mm, linear.rows / page_px_per_mm);
  auto scan_of_page_pixel = [&](double u, double v) {
    return ScanPixelOfPagePoint({(u + 0.5) / page_px_per_mm, (v + 0.5) / page_px_per_mm},
                                page_size_mm, PrintGeometry{}, scanner);
  };
  const cv::Point2d origin = scan_of_page_pixel(0, 0);
  const cv::Point2d du = scan_of_page_pixel(1, 0) - origin, dv = scan_of_page_pixel(0, 1) - origin;
  const cv::Matx23d scan_from_page(du.x, dv.x, origin.x, du.y, dv.y, origin.y);
  const cv::Size scan_size(static_cast<int>(std::lround(scanner.glass_width_mm * scan_px_per_mm)),
                           static_cast<int>(std::lround(scanner.glass_height_mm * scan_px_per_mm)));
  cv::Mat scan;
  // The lid over the glass: a white a little greyer than the paper.
  cv::warpAffine(linear, scan, scan_from_page, scan_size, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                 cv::Scalar::all(kLidWhite));
  SimCamera optics;  // Develop's exposure, blur, sRGB curve and noise.
  optics.gains = {1.0, 1.0, 1.0};
  optics.exposure = scanner.exposure;
  optics.gamma = 0.0;
  optics.blur_sigma_px = scanner.blur_sigma_px;
  optics.noise_sigma = scanner.noise_sigma;
  optics.seed = scanner.seed;
  return Develop(scan, optics);
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
  const cv::Mat linear_tag = PrintAndSee(
      bgr, [&](const Rgb8& sent) { return printer.Print(sent); }, camera);
  cv::Mat scene(height, width, CV_32FC3, cv::Scalar(0.3, 0.3, 0.3));
  const int x0 = (width - tag.width) / 2, y0 = (height - tag.height) / 2;
  linear_tag.copyTo(scene(cv::Rect(x0, y0, tag.width, tag.height)));
  return Develop(scene, camera);
}

std::array<cv::Point2d, 4> PinholePageCorners(const PageSize& page, double f, double tilt_deg,
                                              double yaw_deg, double distance_mm, cv::Size size) {
  const double t = tilt_deg * CV_PI / 180, y = yaw_deg * CV_PI / 180;
  const cv::Matx33d rx(1, 0, 0, 0, std::cos(t), -std::sin(t), 0, std::sin(t), std::cos(t));
  const cv::Matx33d ry(std::cos(y), 0, std::sin(y), 0, 1, 0, -std::sin(y), 0, std::cos(y));
  std::array<cv::Point2d, 4> out;
  const double w = page.width_mm / 2, h = page.height_mm / 2;
  const cv::Vec3d corners[4] = {{-w, -h, 0}, {w, -h, 0}, {w, h, 0}, {-w, h, 0}};
  for (int i = 0; i < 4; ++i) {
    const cv::Vec3d p = ry * rx * corners[i] + cv::Vec3d(0, 0, distance_mm);
    out[i] = {f * p[0] / p[2] + (size.width - 1) / 2.0, f * p[1] / p[2] + (size.height - 1) / 2.0};
  }
  return out;
}

}  // namespace chromatag::testing
