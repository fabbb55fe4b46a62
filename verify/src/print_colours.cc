// The print check's colour measurement (print_colours.h). A tag's black
// square is mapped to the unit square (cv::getPerspectiveTransform); the
// paper white is read all round its quiet zone, each payload cell over its
// central half (5 x 5 bilinear samples in linear light), and every reading
// is normalised to that white before it goes to CIELAB.
#include "print_colours.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "print_internal.h"

namespace chromatag::internal {
namespace {

// Bilinear sample of `bgr` at `p` in linear light (R, G, B); false outside.
bool SampleLinear(const cv::Mat& bgr, const cv::Point2d& p, Rgb* out) {
  // Checked as doubles before any cast: a far or degenerate fit can put a
  // point anywhere, NaN included.
  if (!(p.x >= 0 && p.y >= 0 && p.x < bgr.cols - 1 && p.y < bgr.rows - 1)) return false;
  const int x0 = static_cast<int>(p.x), y0 = static_cast<int>(p.y);
  const double fx = p.x - x0, fy = p.y - y0;
  double c[3] = {0, 0, 0};
  const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  const cv::Vec3b* q[4] = {&bgr.at<cv::Vec3b>(y0, x0), &bgr.at<cv::Vec3b>(y0, x0 + 1),
                           &bgr.at<cv::Vec3b>(y0 + 1, x0), &bgr.at<cv::Vec3b>(y0 + 1, x0 + 1)};
  for (int k = 0; k < 4; ++k) {
    for (int ch = 0; ch < 3; ++ch) c[ch] += w[k] * Srgb8ToLinear((*q[k])[2 - ch]);
  }
  *out = Rgb{c[0], c[1], c[2]};
  return true;
}

Lab NormalisedLab(const Rgb& linear, const Rgb& white) {
  return XyzToLab(
      LinearRgbToXyz({linear.r / std::max(white.r, 1e-6), linear.g / std::max(white.g, 1e-6),
                      linear.b / std::max(white.b, 1e-6)}));
}

Rgb Mean(const std::vector<Rgb>& values) {
  Rgb m;
  for (const Rgb& v : values) {
    m.r += v.r / values.size();
    m.g += v.g / values.size();
    m.b += v.b / values.size();
  }
  return m;
}

double StdDev(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / values.size();
  double sum = 0.0;
  for (double v : values) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / (values.size() - 1));
}

// Maps the black square as the unit square (x right, y down) to pixels, as
// Detection::image_from_tag does for a detection; here also for corners the
// page fit predicts and for candidates that did not decode.
cv::Matx33d ImageFromUnit(const std::array<cv::Point2d, 4>& corners) {
  const cv::Point2f src[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  cv::Point2f dst[4];
  for (int i = 0; i < 4; ++i) dst[i] = cv::Point2f(corners[i]);
  return cv::Matx33d(cv::getPerspectiveTransform(src, dst));
}

// The paper white of a tag: the middle half of its quiet zone, all round,
// trimmed of its darkest and brightest fifth (a label or a speck of dust).
std::optional<Rgb> QuietZoneWhite(const cv::Mat& bgr, const cv::Matx33d& image_from_unit,
                                  double cell, int quiet_zone_cells) {
  std::vector<Rgb> samples;
  const double q = quiet_zone_cells * cell;
  for (double depth : {0.3, 0.5, 0.7}) {
    const double lo = -depth * q, hi = 1.0 + depth * q;
    for (int i = 0; i <= 16; ++i) {
      const double t = lo + (hi - lo) * i / 16.0;
      for (const cv::Point2d& u :
           {cv::Point2d(t, lo), cv::Point2d(t, hi), cv::Point2d(lo, t), cv::Point2d(hi, t)}) {
        Rgb rgb;
        if (SampleLinear(bgr, ApplyHomography(image_from_unit, u), &rgb)) samples.push_back(rgb);
      }
    }
  }
  if (samples.size() < 20) return std::nullopt;
  auto luminance = [](const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  std::sort(samples.begin(), samples.end(),
            [&](const Rgb& a, const Rgb& b) { return luminance(a) < luminance(b); });
  const size_t drop = samples.size() / 5;
  return Mean(std::vector<Rgb>(samples.begin() + drop, samples.end() - drop));
}

struct CellReading {
  Rgb linear;                           // Mean over the cell's central half.
  Lab lab;                              // Normalised to the paper.
  Lab as_shot;                          // Of the mean.
  double noise_a = 0.0, noise_b = 0.0;  // Single samples' as-shot spread.
};

// Reads the payload cell (row, col) of a tag placed by `image_from_unit`.
std::optional<CellReading> ReadCell(const cv::Mat& bgr, const cv::Matx33d& image_from_unit,
                                    double cell, int row, int col, const Rgb& white) {
  constexpr int kGrid = 5;
  std::vector<Rgb> samples;
  std::vector<double> a, b;
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const double u = (col + 1 + 0.25 + 0.5 * (j + 0.5) / kGrid) * cell;
      const double v = (row + 1 + 0.25 + 0.5 * (i + 0.5) / kGrid) * cell;
      Rgb rgb;
      if (!SampleLinear(bgr, ApplyHomography(image_from_unit, {u, v}), &rgb)) return std::nullopt;
      samples.push_back(rgb);
      const Lab lab = XyzToLab(LinearRgbToXyz(rgb));
      a.push_back(lab.a);
      b.push_back(lab.b);
    }
  }
  CellReading r;
  r.linear = Mean(samples);
  r.lab = NormalisedLab(r.linear, white);
  r.as_shot = XyzToLab(LinearRgbToXyz(r.linear));
  r.noise_a = StdDev(a);
  r.noise_b = StdDev(b);
  return r;
}

// Every payload cell of a tag, with its colour and, if `code` is given, its
// shade (index into Shade).
struct TagCells {
  Rgb white;
  std::vector<CellReading> cells;
  std::vector<CellColor> colors;
  std::vector<int> shades;
};

std::optional<TagCells> ReadTagCells(const cv::Mat& bgr, const std::array<cv::Point2d, 4>& corners,
                                     const TagFamily& family, int quiet_zone_cells,
                                     std::optional<Code> code) {
  const cv::Matx33d h = ImageFromUnit(corners);
  const double cell = 1.0 / family.black_square_cells();
  const auto white = QuietZoneWhite(bgr, h, cell, quiet_zone_cells);
  if (!white) return std::nullopt;
  TagCells out;
  out.white = *white;
  const int d = family.payload_width();
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const auto reading = ReadCell(bgr, h, cell, row, col, *white);
      if (!reading) return std::nullopt;
      const CellColor color = family.CellColorAt(row, col);
      out.cells.push_back(*reading);
      out.colors.push_back(color);
      if (code) {
        const bool bit = family.Bit(*code, row, col);
        const Shade shade = color == CellColor::kRed ? (bit ? Shade::kRed1 : Shade::kRed0)
                                                     : (bit ? Shade::kGreen1 : Shade::kGreen0);
        out.shades.push_back(static_cast<int>(shade));
      }
    }
  }
  return out;
}

PrintedShades ShadesOf(const TagCells& t) {
  PrintedShades out;
  for (int s = 0; s < 4; ++s) {
    std::vector<Rgb> linear;
    std::vector<double> b;
    double noise_a = 0.0, noise_b = 0.0;
    for (size_t i = 0; i < t.cells.size(); ++i) {
      if (t.shades[i] != s) continue;
      linear.push_back(t.cells[i].linear);
      b.push_back(t.cells[i].lab.b);
      noise_a += t.cells[i].noise_a;
      noise_b += t.cells[i].noise_b;
    }
    if (linear.empty()) return out;  // Cannot happen for a kept ID.
    ShadeReading& r = out.shades[s];
    const Rgb mean = Mean(linear);
    r.lab = NormalisedLab(mean, t.white);
    r.as_shot = XyzToLab(LinearRgbToXyz(mean));
    r.repeat_spread_b = StdDev(b);
    r.pixel_noise_a = noise_a / linear.size();
    r.pixel_noise_b = noise_b / linear.size();
    r.count = static_cast<int>(linear.size());
  }
  out.paper_as_shot = XyzToLab(LinearRgbToXyz(t.white));
  out.margins = MarginsOf(out.shades, 100.0, /*seen=*/false);
  out.measured = true;
  return out;
}

double LargestGap(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  double gap = 0.0;
  for (size_t i = 1; i < values.size(); ++i) gap = std::max(gap, values[i] - values[i - 1]);
  return gap;
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

}  // namespace

PrintedShades ReadPrintedShades(const cv::Mat& bgr, const std::array<cv::Point2d, 4>& corners,
                                const TagFamily& family, int quiet_zone_cells, Code code) {
  const auto cells = ReadTagCells(bgr, corners, family, quiet_zone_cells, code);
  return cells ? ShadesOf(*cells) : PrintedShades();
}

// Candidates the detector gave up on at Decode, with their cells' splits.
std::vector<UndecodedCandidate> Undecoded(const cv::Mat& bgr, const DetectionResult& result,
                                          const SheetRecord& record) {
  std::vector<UndecodedCandidate> out;
  for (const RejectedCandidate& r : result.rejected) {
    if (r.stage != Stage::kDecode || r.outline.size() != 4) continue;
    UndecodedCandidate u;
    for (int c = 0; c < 4; ++c) u.corners_px[c] = cv::Point2d(r.outline[c]);
    const auto cells =
        ReadTagCells(bgr, u.corners_px, *record.family, record.quiet_zone_cells, std::nullopt);
    if (!cells) continue;
    std::vector<double> red_b, green_b, red_a, green_a;
    for (size_t i = 0; i < cells->cells.size(); ++i) {
      const Lab& lab = cells->cells[i].lab;
      if (cells->colors[i] == CellColor::kRed) {
        red_b.push_back(lab.b);
        red_a.push_back(lab.a);
      } else {
        green_b.push_back(lab.b);
        green_a.push_back(lab.a);
      }
    }
    u.red_b_split = LargestGap(red_b);
    u.green_b_split = LargestGap(green_b);
    u.a_gap = Median(red_a) - Median(green_a);
    out.push_back(u);
  }
  return out;
}

}  // namespace chromatag::internal
