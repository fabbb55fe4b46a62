// Sampling one patch robustly (sample_patch.h).
#include "sample_patch.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "chromatag/calib/locate_sheet.h"

namespace chromatag::internal {
namespace {

double TrimmedMean(std::vector<double>* values, double trim) {
  if (values->empty()) return 0.0;
  std::sort(values->begin(), values->end());
  const size_t cut = static_cast<size_t>(trim * values->size());
  double sum = 0;
  for (size_t i = cut; i < values->size() - cut; ++i) sum += (*values)[i];
  return sum / (values->size() - 2 * cut);
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

double StdDev(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  double mean = 0, sq = 0;
  for (double v : values) mean += v;
  mean /= values.size();
  for (double v : values) sq += (v - mean) * (v - mean);
  return std::sqrt(sq / (values.size() - 1));
}

// Pixels of `bgr` whose centre maps inside the page square centred on
// `centre` with side `side` (mm).
std::vector<cv::Vec3b> PixelsInSquare(const cv::Mat& bgr, const cv::Matx33d& image_from_page,
                                      const std::array<double, 2>& centre, double side) {
  const cv::Matx33d page_from_image = image_from_page.inv();
  const double h = side / 2.0;
  double x_min = 1e300, x_max = -1e300, y_min = 1e300, y_max = -1e300;
  for (const auto& c : {std::array<double, 2>{centre[0] - h, centre[1] - h},
                        std::array<double, 2>{centre[0] + h, centre[1] - h},
                        std::array<double, 2>{centre[0] + h, centre[1] + h},
                        std::array<double, 2>{centre[0] - h, centre[1] + h}}) {
    const cv::Point2d p = PageToImage(image_from_page, c);
    x_min = std::min(x_min, p.x);
    x_max = std::max(x_max, p.x);
    y_min = std::min(y_min, p.y);
    y_max = std::max(y_max, p.y);
  }
  std::vector<cv::Vec3b> out;
  // Bounded to the image as doubles before the casts (NaN: nothing to sample).
  if (!(x_min <= x_max && y_min <= y_max)) return {};
  auto inside = [](double v, int size) {
    return static_cast<int>(std::clamp(v, -1.0, static_cast<double>(size)));
  };
  const int x0 = std::max(0, inside(std::floor(x_min), bgr.cols));
  const int x1 = std::min(bgr.cols - 1, inside(std::ceil(x_max), bgr.cols));
  const int y0 = std::max(0, inside(std::floor(y_min), bgr.rows));
  const int y1 = std::min(bgr.rows - 1, inside(std::ceil(y_max), bgr.rows));
  for (int y = y0; y <= y1; ++y) {
    const cv::Vec3b* row = bgr.ptr<cv::Vec3b>(y);
    for (int x = x0; x <= x1; ++x) {
      const cv::Vec3d q = page_from_image * cv::Vec3d(x, y, 1.0);
      const double u = q[0] / q[2] - centre[0], v = q[1] / q[2] - centre[1];
      if (std::abs(u) <= h && std::abs(v) <= h) out.push_back(row[x]);
    }
  }
  return out;
}

Rgb TrimmedLinearMean(const std::vector<cv::Vec3b>& pixels, double trim) {
  std::vector<double> r, g, b;
  r.reserve(pixels.size());
  g.reserve(pixels.size());
  b.reserve(pixels.size());
  for (const cv::Vec3b& p : pixels) {
    b.push_back(Srgb8ToLinear(p[0]));
    g.push_back(Srgb8ToLinear(p[1]));
    r.push_back(Srgb8ToLinear(p[2]));
  }
  return {TrimmedMean(&r, trim), TrimmedMean(&g, trim), TrimmedMean(&b, trim)};
}

}  // namespace

PatchPixels SamplePatch(const cv::Mat& bgr, const cv::Matx33d& image_from_page, const Patch& patch,
                        const MeasureOptions& options) {
  PatchPixels out;
  const auto centre = patch.CenterMm();
  const std::vector<cv::Vec3b> pixels =
      PixelsInSquare(bgr, image_from_page, centre, patch.size_mm * options.central_fraction);
  const std::vector<cv::Vec3b> inner =
      PixelsInSquare(bgr, image_from_page, centre, patch.size_mm * options.inner_fraction);
  out.pixels = static_cast<int>(pixels.size());
  if (pixels.empty()) return out;
  out.linear_mean = TrimmedLinearMean(pixels, options.trim);
  out.inner_linear_mean = inner.empty() ? out.linear_mean : TrimmedLinearMean(inner, options.trim);

  int high = 0, zero = 0;
  std::vector<double> luminance;
  luminance.reserve(pixels.size());
  for (const cv::Vec3b& p : pixels) {
    high += std::max({p[0], p[1], p[2]}) >= 254;
    zero += std::min({p[0], p[1], p[2]}) == 0;
    luminance.push_back(
        LinearRgbToXyz(Rgb{Srgb8ToLinear(p[2]), Srgb8ToLinear(p[1]), Srgb8ToLinear(p[0])}).Y);
  }
  out.clipped_high = static_cast<double>(high) / pixels.size();
  out.clipped_zero = static_cast<double>(zero) / pixels.size();
  out.y_p02 = Percentile(luminance, 0.02);
  out.y_p50 = Percentile(luminance, 0.5);
  out.y_p98 = Percentile(luminance, 0.98);

  // Noise from up to ~400 pixels spread over the square.
  std::vector<double> a, b;
  const size_t stride = std::max<size_t>(1, pixels.size() / 400);
  for (size_t i = 0; i < pixels.size(); i += stride) {
    const Lab lab = SrgbToLab(Rgb8{pixels[i][2], pixels[i][1], pixels[i][0]});
    a.push_back(lab.a);
    b.push_back(lab.b);
  }
  out.noise_a = StdDev(a);
  out.noise_b = StdDev(b);
  return out;
}

}  // namespace chromatag::internal
