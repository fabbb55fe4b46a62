#include "chromatag/verify/print_check.h"

#include "print_internal.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/families/color.h"

namespace chromatag {
namespace {

constexpr double kMmPerInch = 25.4;
using internal::Format;

// ---------------------------------------------------------------------------
// Sampling colours.

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

cv::Point2d Apply(const cv::Matx33d& h, const cv::Point2d& p) {
  const cv::Vec3d v = h * cv::Vec3d(p.x, p.y, 1.0);
  return {v[0] / v[2], v[1] / v[2]};
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

// Maps the black square as the unit square (x right, y down) to pixels.
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
        if (SampleLinear(bgr, Apply(image_from_unit, u), &rgb)) samples.push_back(rgb);
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
      if (!SampleLinear(bgr, Apply(image_from_unit, {u, v}), &rgb)) return std::nullopt;
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
  out.margins = MarginsOf(out.shades, 100.0, /*as_shot=*/false);
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

// ---------------------------------------------------------------------------
// Fitting the page.

struct Pair {
  int tag = 0;        // Index into the page's tags.
  int detection = 0;  // Index into the detections.
};

struct PageFit {
  cv::Matx33d image_from_page = cv::Matx33d::eye();
  std::vector<int> kept;  // Pairs the fit kept.
  double rms_mm = 0.0;
  // Scans: the affine's parameters' standard errors (x and y columns).
  double se_x = 0.0, se_y = 0.0;
};

// Least squares: page mm -> `image` points (scan mm for a scan, pixels for a
// photo), affine or projective.
bool FitOnce(const std::vector<cv::Point2d>& page, const std::vector<cv::Point2d>& image,
             bool affine, PageFit* fit) {
  if (affine) {
    cv::Mat a(static_cast<int>(page.size()), 3, CV_64F), bx(a.rows, 1, CV_64F),
        by(a.rows, 1, CV_64F);
    for (int i = 0; i < a.rows; ++i) {
      a.at<double>(i, 0) = page[i].x;
      a.at<double>(i, 1) = page[i].y;
      a.at<double>(i, 2) = 1.0;
      bx.at<double>(i) = image[i].x;
      by.at<double>(i) = image[i].y;
    }
    cv::Mat px, py;
    if (!cv::solve(a, bx, px, cv::DECOMP_SVD) || !cv::solve(a, by, py, cv::DECOMP_SVD))
      return false;
    fit->image_from_page =
        cv::Matx33d(px.at<double>(0), px.at<double>(1), px.at<double>(2), py.at<double>(0),
                    py.at<double>(1), py.at<double>(2), 0, 0, 1);
    const cv::Mat rx = a * px - bx, ry = a * py - by;
    const int dof = 2 * a.rows - 6;
    if (dof > 0) {
      const double s2 = (rx.dot(rx) + ry.dot(ry)) / dof;
      const cv::Mat m = (a.t() * a).inv(cv::DECOMP_SVD);
      fit->se_x = std::sqrt(s2 * m.at<double>(0, 0));
      fit->se_y = std::sqrt(s2 * m.at<double>(1, 1));
    }
    return true;
  }
  const cv::Mat h = cv::findHomography(page, image, 0);
  if (h.empty()) return false;
  fit->image_from_page = cv::Matx33d(h);
  return true;
}

// Fits over every pair's four corners, then drops the tag that lies worst
// off the fit while it lies more than `drop_mm` off, refitting each time
// (never below two tags). Residuals are measured on the page.
std::optional<PageFit> FitPage(const std::vector<PlacedTag>& tags,
                               const std::vector<std::array<cv::Point2d, 4>>& found_corners,
                               const std::vector<Pair>& pairs, bool affine, double drop_mm) {
  std::vector<int> kept(pairs.size());
  std::iota(kept.begin(), kept.end(), 0);
  while (true) {
    std::vector<cv::Point2d> page, image;
    for (int k : kept) {
      for (int c = 0; c < 4; ++c) {
        page.emplace_back(tags[pairs[k].tag].corners_mm[c][0], tags[pairs[k].tag].corners_mm[c][1]);
        image.push_back(found_corners[pairs[k].detection][c]);
      }
    }
    PageFit fit;
    if (!FitOnce(page, image, affine, &fit)) return std::nullopt;
    const cv::Matx33d page_from_image = fit.image_from_page.inv();
    double worst = 0.0, sum2 = 0.0;
    size_t worst_k = 0;
    std::vector<double> tag_errors;
    for (size_t i = 0; i < kept.size(); ++i) {
      double tag_worst = 0.0;
      for (int c = 0; c < 4; ++c) {
        const cv::Point2d back = Apply(page_from_image, image[4 * i + c]);
        const double e = cv::norm(back - page[4 * i + c]);
        sum2 += e * e;
        tag_worst = std::max(tag_worst, e);
      }
      tag_errors.push_back(tag_worst);
      if (tag_worst > worst) worst = tag_worst, worst_k = i;
    }
    fit.rms_mm = std::sqrt(sum2 / std::max<size_t>(1, page.size()));
    // An outlier lies off by more than drop_mm and well beyond the others:
    // a curled page or a distorting lens moves every tag a little, and
    // dropping them one by one would leave a fit over two.
    std::nth_element(tag_errors.begin(), tag_errors.begin() + tag_errors.size() / 2,
                     tag_errors.end());
    const double typical = tag_errors[tag_errors.size() / 2];
    if (worst <= std::max(drop_mm, 4.0 * typical) || kept.size() <= 2) {
      fit.kept = kept;
      return fit;
    }
    kept.erase(kept.begin() + worst_k);
  }
}

// The page's x scale over its y scale in a photo, from the homography and
// the camera (K): H ~ K [r1 r2 t] diag(sx, sy, 1).
double AspectOf(const cv::Matx33d& h, const cv::Matx33d& k) {
  const cv::Matx33d m = k.inv() * h;
  const double n1 = std::hypot(std::hypot(m(0, 0), m(1, 0)), m(2, 0));
  const double n2 = std::hypot(std::hypot(m(0, 1), m(1, 1)), m(2, 1));
  return n1 / n2;
}

// Focal length from the orthogonality of the page's axes with the principal
// point at (cx, cy) and square pixels; nullopt when the view is too close
// to face-on (or too noisy) to tell.
std::optional<double> EstimateFocal(const cv::Matx33d& h, double cx, double cy, double width) {
  const cv::Matx33d t(1, 0, -cx, 0, 1, -cy, 0, 0, 1);
  const cv::Matx33d g = t * h;
  const double num = -(g(0, 0) * g(0, 1) + g(1, 0) * g(1, 1));
  const double den = g(2, 0) * g(2, 1);
  if (std::abs(den) < 1e-15) return std::nullopt;
  const double f2 = num / den;
  if (!(f2 > 0)) return std::nullopt;
  const double f = std::sqrt(f2);
  if (f < 0.25 * width || f > 8.0 * width) return std::nullopt;
  return f;
}

struct AspectEstimate {
  double aspect = 0.0;  // 0 when the points give no homography.
  double focal = 0.0;
  bool focal_found = false;  // Estimated from the perspective (or given).
};

// The page's aspect from page points and their (undistorted) pixels, with
// the camera `k` if known, else a focal length from the page's perspective
// and the principal point at (cx, cy).
AspectEstimate EstimateAspect(const std::vector<cv::Point2d>& page,
                              const std::vector<cv::Point2d>& image,
                              const std::optional<cv::Matx33d>& k, double cx, double cy,
                              double width) {
  AspectEstimate out;
  const cv::Mat hm = cv::findHomography(page, image, 0);
  if (hm.empty()) return out;
  const cv::Matx33d h(hm);
  if (k) {
    out.focal = std::sqrt((*k)(0, 0) * (*k)(1, 1));
    out.focal_found = true;
    out.aspect = AspectOf(h, *k);
    return out;
  }
  const auto f = EstimateFocal(h, cx, cy, width);
  out.focal_found = f.has_value();
  out.focal = f ? *f : 0.87 * width;
  out.aspect = AspectOf(h, cv::Matx33d(out.focal, 0, cx, 0, out.focal, cy, 0, 0, 1));
  return out;
}

// ---------------------------------------------------------------------------
// Judging.

struct Finding {
  Grade grade;
  std::string text;
};

void Add(std::vector<Finding>* findings, Grade grade, std::string text) {
  findings->push_back({grade, std::move(text)});
}

void Settle(std::vector<Finding> findings, Grade* grade, std::vector<std::string>* problems,
            std::vector<Grade>* grades) {
  std::stable_sort(findings.begin(), findings.end(), [](const Finding& a, const Finding& b) {
    return static_cast<int>(a.grade) > static_cast<int>(b.grade);
  });
  *grade = Grade::kPass;
  for (const Finding& f : findings) {
    *grade = std::max(*grade, f.grade);
    problems->push_back(f.text);
    grades->push_back(f.grade);
  }
}

void JudgeBGap(const char* colour, Shade one, Shade zero, double gap, double decision,
               const PrintedShades& c, const Palette& palette, double need,
               const PrintCheckOptions& o, std::vector<Finding>* findings) {
  const double b1 = c.shades[static_cast<int>(one)].lab.b;
  const double b0 = c.shades[static_cast<int>(zero)].lab.b;
  const double design =
      palette.lab[static_cast<int>(one)].b - palette.lab[static_cast<int>(zero)].b;
  if (gap <= 0) {
    Add(findings, Grade::kFail,
        Format("%s shades printed swapped: %s at b* %.1f, %s at b* %.1f (the palette has them "
               "%.1f apart the other way)",
               colour, ShadeName(one), b1, ShadeName(zero), b0, std::abs(design)));
  } else if (decision < need) {
    Add(findings, Grade::kFail,
        Format("%s b* split %.1f (palette %.1f) is gone: decision margin %.1f, the detector "
               "needs %.1f",
               colour, gap, std::abs(design), decision, need));
  } else if (gap < o.thin_b_gap || (need > 0 && decision < o.thin_factor * need)) {
    Add(findings, Grade::kWarn,
        Format("%s b* split %.1f (palette %.1f) is thin: decision margin %.1f, %.1f needed", colour,
               gap, std::abs(design), decision, need));
  }
}

void JudgeColours(const PrintedShades& c, const TagFamily& family, const Palette& palette,
                  const PrintCheckOptions& o, std::vector<Finding>* findings) {
  if (!c.measured) return;
  const Margins& m = c.margins;
  const DetectorOptions& d = o.detector;
  if (m.a_gap < d.adiff_thresh) {
    Add(findings, Grade::kFail,
        Format("reds and greens only %.1f apart in a*, below ADiffThresh %.1f", m.a_gap,
               d.adiff_thresh));
  } else if (m.a_gap < o.thin_factor * d.adiff_thresh) {
    Add(findings, Grade::kWarn,
        Format("reds and greens %.1f apart in a*: under %.0fx ADiffThresh %.1f", m.a_gap,
               o.thin_factor, d.adiff_thresh));
  }
  if (m.min_red_a < kMinTagRedA) {
    Add(findings, Grade::kFail,
        Format("the paler red prints at a* %.1f, below the detector's floor of %.0f for a red",
               m.min_red_a, kMinTagRedA));
  }
  if (m.max_green_a > d.max_green_a) {
    Add(findings, Grade::kFail,
        Format("the redder green prints at a* %.1f, above max_green_a %.1f", m.max_green_a,
               d.max_green_a));
  }
  // What an exact read of this family needs (decode.cc); a corrected bit
  // is a fault of its own, judged from the detection.
  const double need = d.min_decision_margin * DecisionMarginFactor(family, 0);
  JudgeBGap("red", Shade::kRed1, Shade::kRed0, m.red_b_gap, m.red_decision, c, palette, need, o,
            findings);
  JudgeBGap("green", Shade::kGreen0, Shade::kGreen1, m.green_b_gap, m.green_decision, c, palette,
            need, o, findings);
}

cv::Point2d Centre(const std::array<cv::Point2d, 4>& q) {
  return (q[0] + q[1] + q[2] + q[3]) * 0.25;
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

// The page of the sheet most detections belong to, by ID; -1 for none.
int ChoosePage(const SheetRecord& record, const std::vector<const Detection*>& mine) {
  std::vector<int> votes(std::max(1, record.num_pages), 0);
  for (const Detection* d : mine) {
    std::vector<bool> voted(votes.size(), false);
    for (const PlacedTag& t : record.tags) {
      if (t.id == d->id && t.page < static_cast<int>(votes.size()) && !voted[t.page]) {
        ++votes[t.page];
        voted[t.page] = true;
      }
    }
  }
  const auto best = std::max_element(votes.begin(), votes.end());
  return *best > 0 ? static_cast<int>(best - votes.begin()) : -1;
}

void JudgePage(const PrintCheckOptions& o, const SheetRecord& record, PrintPageResult* r,
               std::vector<Finding>* findings) {
  r->geometry_checked = true;  // Unless a branch below says otherwise.
  if (r->scan) {
    const double tol = o.max_scale_error;
    const double ex = std::max(0.001, 2 * r->scale_x_error),
                 ey = std::max(0.001, 2 * r->scale_y_error);
    const bool x_off = std::abs(r->scale_x - 1.0) > tol, y_off = std::abs(r->scale_y - 1.0) > tol;
    if ((x_off || y_off) && std::abs(r->scale_x - r->scale_y) <= tol) {
      const double mean = (r->scale_x + r->scale_y) / 2;
      Add(findings, Grade::kFail,
          Format("printed at %.1f %% of its size (scale x %.3f ± %.3f, y %.3f ± %.3f; "
                 "allowed 1 ± %.3f): %.1f mm tags print as %.2f mm. Print at 100 %% "
                 "(\"actual size\"), not \"fit to page\"",
                 100 * mean, r->scale_x, ex, r->scale_y, ey, tol, record.tag_size_mm,
                 record.tag_size_mm * mean));
    } else if (x_off || y_off) {
      Add(findings, Grade::kFail,
          Format("stretched: scale x %.3f ± %.3f, y %.3f ± %.3f (allowed 1 ± %.3f each): the "
                 "printer does not keep the page's aspect; poses from these tags will be off",
                 r->scale_x, ex, r->scale_y, ey, tol));
    }
    if (std::abs(r->skew_deg) > 0.5) {
      Add(findings, Grade::kWarn,
          Format("the page's axes are %.1f degrees from square (the paper fed crooked)",
                 r->skew_deg));
    }
  } else if (r->aspect == 0) {
    r->geometry_checked = false;
    Add(findings, Grade::kWarn,
        Format("the page's shape was not checked: only %d tag%s fit, too few to judge its aspect "
               "(4 or more)",
               r->tags_in_fit, r->tags_in_fit == 1 ? "" : "s"));
  } else if (std::abs(r->aspect - 1.0) > o.max_aspect_error + 2 * r->aspect_error) {
    Add(findings, Grade::kFail,
        Format("stretched: the page's x scale over its y scale is %.3f ± %.3f (allowed 1 ± %.3f)",
               r->aspect, 2 * r->aspect_error, o.max_aspect_error));
  } else if (2 * r->aspect_error > o.max_aspect_error) {
    // The view leaves the aspect too loose to catch a stretch of the
    // tolerance's size (a tilt about one image axis leaves the focal length
    // free, and the aspect trades with it): passing it would vouch for what
    // was not seen.
    r->geometry_checked = false;
    Add(findings, Grade::kWarn,
        Format("the page's shape was not checked: this view gives its aspect only as %.3f ± %.3f, "
               "where 1 ± %.3f is allowed (the view does not fix the camera's focal length); "
               "give --camera, add a photo tilted about both axes or face on, or scan the page",
               r->aspect, 2 * r->aspect_error, o.max_aspect_error));
  }
  if (r->tags_in_fit >= 3 && r->rms_mm > 0.5 * o.max_position_error_mm) {
    Add(findings, Grade::kWarn,
        Format("the tags do not lie on one flat page (fit residual %.2f mm rms): the sheet "
               "curls%s",
               r->rms_mm, r->scan ? "" : " or the lens distorts (give --camera)"));
  }
  // A tag of the sheet's family, read exactly, on the page where the sidecar
  // lists none means the sidecar does not describe this print (cut down, or
  // another sheet's); one beside the page, of another family or read with
  // corrected bits may be something else in view.
  for (const UnexpectedDetection& u : r->unexpected) {
    const bool on_page = u.exact && u.center_mm[0] >= 0 && u.center_mm[0] <= record.page.width_mm &&
                         u.center_mm[1] >= 0 && u.center_mm[1] <= record.page.height_mm;
    Add(findings, on_page ? Grade::kFail : Grade::kWarn,
        Format("%s ID %d found at %.1f, %.1f mm, where the sidecar has no tag%s", u.family.c_str(),
               u.id, u.center_mm[0], u.center_mm[1],
               on_page ? ": the sidecar does not describe this print" : ""));
  }
}

void JudgeTag(const PrintCheckOptions& o, const SheetRecord& record, bool scan,
              double size_allowance, PrintTagResult* t) {
  // What the print did first (the cause), then what the detector made of it.
  std::vector<Finding> findings;
  // A tag's own width carries the detector's corner bias on blurred edges
  // (about 0.3 px an edge, inwards): a pixel is allowed on top.
  const double size_ratio = t->size_mm / record.tag_size_mm;
  if (scan && t->size_mm > 0 && std::abs(size_ratio - 1.0) > o.max_scale_error + size_allowance) {
    Add(&findings, Grade::kFail,
        Format("prints %.2f mm wide where the sidecar says %.2f mm (%.1f %%)", t->size_mm,
               record.tag_size_mm, 100 * size_ratio));
  }
  JudgeColours(t->colours, *record.family, record.palette, o, &findings);
  if (!t->found) {
    Add(&findings, Grade::kFail, "not found");
  } else if (t->found_id != t->expected.id) {
    Add(&findings, Grade::kFail, Format("decodes as ID %d", t->found_id));
  } else if (t->hamming > 0) {
    Add(&findings, scan ? Grade::kFail : Grade::kWarn,
        Format("decodes only with %d bit%s corrected: a cell reads as the wrong shade", t->hamming,
               t->hamming == 1 ? "" : "s"));
  }
  if (t->found && t->position_error_mm > o.max_position_error_mm) {
    Add(&findings, Grade::kWarn,
        Format("lies %.2f mm from where the other tags put it", t->position_error_mm));
  }
  Settle(std::move(findings), &t->grade, &t->problems, &t->problem_grades);
}

// ---------------------------------------------------------------------------
// CheckPrintImage's stages.

// Where the page is fitted: scan millimetres for a scan; for a photo,
// pixels, undistorted when the camera's distortion is known.
class FitSpace {
 public:
  FitSpace(const PrintImage& image, const std::optional<CameraIntrinsics>& camera)
      : scan_(image.dpi_x > 0 && image.dpi_y > 0),
        mm_per_px_x_(scan_ ? kMmPerInch / image.dpi_x : 1.0),
        mm_per_px_y_(scan_ ? kMmPerInch / image.dpi_y : 1.0) {
    if (!scan_ && camera && !camera->distortion.empty()) camera_ = camera;
  }
  bool scan() const { return scan_; }

  cv::Point2d FromImage(const cv::Point2d& px) const {
    if (scan_) return {px.x * mm_per_px_x_, px.y * mm_per_px_y_};
    if (!camera_) return px;
    return UndistortPoints(*camera_, {px})[0];
  }
  std::vector<cv::Point2d> ToImage(const std::vector<cv::Point2d>& points) const {
    std::vector<cv::Point2d> out;
    if (scan_ || !camera_) {
      for (const cv::Point2d& p : points)
        out.push_back(scan_ ? cv::Point2d(p.x / mm_per_px_x_, p.y / mm_per_px_y_) : p);
      return out;
    }
    // Undistorted pixels to normalised rays, then through the lens.
    std::vector<cv::Point3d> rays;
    const cv::Matx33d k_inv = CameraMatrix(*camera_).inv();
    for (const cv::Point2d& p : points) {
      const cv::Vec3d ray = k_inv * cv::Vec3d(p.x, p.y, 1.0);
      rays.emplace_back(ray[0] / ray[2], ray[1] / ray[2], 1.0);
    }
    return ProjectPoints(*camera_, rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0));
  }
  cv::Point2d ToImage(const cv::Point2d& p) const { return ToImage(std::vector{p})[0]; }
  // From fit space to undistorted pixels (for image_from_page).
  cv::Matx33d PixelsFromFit() const {
    return scan_ ? cv::Matx33d(1 / mm_per_px_x_, 0, 0, 0, 1 / mm_per_px_y_, 0, 0, 0, 1)
                 : cv::Matx33d::eye();
  }

 private:
  bool scan_;
  double mm_per_px_x_, mm_per_px_y_;
  std::optional<CameraIntrinsics> camera_;  // A photo through a lens with distortion.
};

// The image resampled onto the page, `s` pixels a millimetre.
cv::Mat PageView(const cv::Mat& bgr, const cv::Matx33d& fit_from_page, const FitSpace& space,
                 const PageSize& page, double s) {
  const cv::Size size(std::max(1, static_cast<int>(std::lround(page.width_mm * s))),
                      std::max(1, static_cast<int>(std::lround(page.height_mm * s))));
  // View pixel (u, v) is page mm ((u + 0.5) / s, (v + 0.5) / s).
  std::vector<cv::Point2d> fit;
  fit.reserve(static_cast<size_t>(size.area()));
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u)
      fit.push_back(Apply(fit_from_page, {(u + 0.5) / s, (v + 0.5) / s}));
  const std::vector<cv::Point2d> image = space.ToImage(fit);
  cv::Mat map(size, CV_32FC2);
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      const cv::Point2d& p = image[static_cast<size_t>(v) * size.width + u];
      map.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(p.x), static_cast<float>(p.y));
    }
  }
  cv::Mat view;
  cv::remap(bgr, view, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(128, 128, 128));
  return view;
}

// Detections paired with the page's tags by ID. Only IDs the page holds
// once pair (generate never repeats an ID); a tag whose ID appears twice in
// a hand-made sidecar is still found afterwards, by its place on the page.
std::vector<Pair> PairByIds(const std::vector<PlacedTag>& tags,
                            const std::vector<const Detection*>& mine) {
  std::vector<Pair> pairs;
  for (size_t k = 0; k < mine.size(); ++k) {
    int match = -1, count = 0;
    for (size_t i = 0; i < tags.size(); ++i) {
      if (tags[i].id != mine[k]->id) continue;
      match = static_cast<int>(i);
      ++count;
    }
    if (count == 1) pairs.push_back({match, static_cast<int>(k)});
  }
  return pairs;
}

// The scan's printed scale along the page's axes, and their skew.
void MeasureScale(const PageFit& fit, PrintPageResult* r) {
  const cv::Matx33d& a = fit.image_from_page;
  r->scale_x = std::hypot(a(0, 0), a(1, 0));
  r->scale_y = std::hypot(a(0, 1), a(1, 1));
  r->scale_x_error = fit.se_x;
  r->scale_y_error = fit.se_y;
  const double cos_angle =
      (a(0, 0) * a(0, 1) + a(1, 0) * a(1, 1)) / std::max(1e-12, r->scale_x * r->scale_y);
  r->skew_deg = std::asin(std::clamp(cos_angle, -1.0, 1.0)) * 180.0 / kPi;
}

// A photo's aspect, from the kept tags' corners in (undistorted) pixels,
// with its jackknife standard error over the tags.
void MeasureAspect(const std::vector<cv::Point2d>& page, const std::vector<cv::Point2d>& image,
                   const std::optional<CameraIntrinsics>& camera, cv::Size size,
                   PrintPageResult* r) {
  const size_t n = page.size() / 4;
  if (n < 4) return;  // Too few to judge (JudgePage says so).
  std::optional<cv::Matx33d> k;
  if (camera) k = cv::Matx33d(camera->fx, 0, camera->cx, 0, camera->fy, camera->cy, 0, 0, 1);
  const double cx = (size.width - 1) / 2.0, cy = (size.height - 1) / 2.0;
  const AspectEstimate all = EstimateAspect(page, image, k, cx, cy, size.width);
  if (!(all.aspect > 0)) return;
  r->aspect = all.aspect;
  r->focal_px = all.focal;
  r->focal_source = k ? "camera" : all.focal_found ? "perspective" : "guessed";
  std::vector<double> partial;
  for (size_t leave = 0; leave < n; ++leave) {
    std::vector<cv::Point2d> p2, i2;
    for (size_t i = 0; i < page.size(); ++i) {
      if (i / 4 == leave) continue;
      p2.push_back(page[i]);
      i2.push_back(image[i]);
    }
    const AspectEstimate e = EstimateAspect(p2, i2, k, cx, cy, size.width);
    if (e.aspect > 0) partial.push_back(e.aspect);
  }
  if (partial.size() >= 2) {
    const double mean = std::accumulate(partial.begin(), partial.end(), 0.0) / partial.size();
    double sum = 0.0;
    for (double a : partial) sum += (a - mean) * (a - mean);
    r->aspect_error = std::sqrt(sum * (partial.size() - 1) / partial.size());
  }
  if (!k && !all.focal_found) {
    // Face on, the focal length cannot be told, and barely matters: a
    // usual camera's (about 60 degrees across) was taken; let the spread
    // over half to twice it say how little.
    for (double f : {all.focal / 2, all.focal * 2}) {
      const AspectEstimate e =
          EstimateAspect(page, image, cv::Matx33d(f, 0, cx, 0, f, cy, 0, 0, 1), cx, cy, size.width);
      if (e.aspect > 0)
        r->aspect_error = std::max(r->aspect_error, std::abs(e.aspect - r->aspect) / 2);
    }
  }
}

// The worst corner distance, mm on the page, of pair `k`'s tag from where a
// fit over the other kept pairs puts it (from the full fit when it was left
// out of it, or when too few others remain).
double LeaveOneOutError(const std::vector<PlacedTag>& tags,
                        const std::vector<std::array<cv::Point2d, 4>>& fit_corners,
                        const std::vector<Pair>& pairs, const PageFit& fit, int k, bool affine) {
  cv::Matx33d fit_from_page = fit.image_from_page;
  const bool kept = std::find(fit.kept.begin(), fit.kept.end(), k) != fit.kept.end();
  if (kept && fit.kept.size() >= 3) {
    std::vector<cv::Point2d> page, image;
    for (int other : fit.kept) {
      if (other == k) continue;
      for (int c = 0; c < 4; ++c) {
        page.emplace_back(tags[pairs[other].tag].corners_mm[c][0],
                          tags[pairs[other].tag].corners_mm[c][1]);
        image.push_back(fit_corners[pairs[other].detection][c]);
      }
    }
    PageFit without;
    if (FitOnce(page, image, affine, &without)) fit_from_page = without.image_from_page;
  }
  const cv::Matx33d page_from_fit = fit_from_page.inv();
  double worst = 0.0;
  for (int c = 0; c < 4; ++c) {
    const cv::Point2d back = Apply(page_from_fit, fit_corners[pairs[k].detection][c]);
    const auto& mm = tags[pairs[k].tag].corners_mm[c];
    worst = std::max(worst, std::hypot(back.x - mm[0], back.y - mm[1]));
  }
  return worst;
}

std::string NoPageProblem(const SheetRecord& record, const DetectionResult& result,
                          const PrintCheckOptions& options, PrintPageResult* r) {
  std::string why = "no tag of the sheet decodes in this image";
  if (r->undecoded.empty()) {
    if (!result.detections.empty()) why += " (only tags of another sheet or family)";
    return why;
  }
  double red = 0, green = 0, a = 0;
  for (const auto& u : r->undecoded) {
    red += u.red_b_split / r->undecoded.size();
    green += u.green_b_split / r->undecoded.size();
    a += u.a_gap / r->undecoded.size();
  }
  why += Format(
      "; %zu tag-like candidate%s fail to decode, their cells' b* split on average %.1f in "
      "the reds and %.1f in the greens (the palette: %.1f and %.1f), a* gap %.1f",
      r->undecoded.size(), r->undecoded.size() == 1 ? "" : "s", red, green,
      std::abs(record.palette.lab[0].b - record.palette.lab[1].b),
      std::abs(record.palette.lab[3].b - record.palette.lab[2].b), a);
  const double need = options.thin_b_gap / 2;
  if (red < need && green >= need) why += ": the two reds print alike";
  if (green < need && red >= need) why += ": the two greens print alike";
  if (red < need && green < need) why += ": neither colour's two shades can be told apart";
  return why;
}

}  // namespace

bool PrintCheckOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (scan_dpi != 0.0 && !(scan_dpi >= 50.0 && scan_dpi <= 4800.0))
    return fail("the scan resolution must be in [50, 4800] dpi");
  if (!(max_scale_error > 0.0 && max_scale_error <= 0.2))
    return fail("the scale tolerance must be in (0, 0.2] (0.005 is 0.5 %)");
  if (!(max_aspect_error > 0.0 && max_aspect_error <= 0.2))
    return fail("the aspect tolerance must be in (0, 0.2]");
  if (!(max_position_error_mm > 0.0 && max_position_error_mm <= 50.0))
    return fail("the position tolerance must be in (0, 50] mm");
  if (!(thin_b_gap >= 0.0 && thin_b_gap <= 100.0) || !(thin_factor >= 1.0 && thin_factor <= 10.0))
    return fail("thin_b_gap must be in [0, 100] and thin_factor in [1, 10]");
  if (camera && !camera->IsValid(error)) return false;
  return detector.IsValid(error);
}

const char* GradeName(Grade grade) {
  switch (grade) {
    case Grade::kPass:
      return "pass";
    case Grade::kWarn:
      return "warn";
    case Grade::kFail:
      return "fail";
  }
  return "?";
}

PrintPageResult CheckPrintImage(const SheetRecord& record, const cv::Mat& bgr,
                                const PrintImage& image, const Detector& detector,
                                const PrintCheckOptions& options) {
  PrintPageResult r;
  r.image = image.name;
  r.image_size = bgr.size();
  const FitSpace space(image, options.camera);
  r.scan = space.scan();
  r.dpi_x = image.dpi_x;
  r.dpi_y = image.dpi_y;
  std::vector<Finding> page_findings;
  auto settle = [&] {
    Settle(std::move(page_findings), &r.grade, &r.problems, &r.problem_grades);
    for (const PrintTagResult& t : r.tags) r.grade = std::max(r.grade, t.grade);
    return r;
  };
  std::string why;
  if (!internal::SheetIsSane(record, &why)) {
    Add(&page_findings, Grade::kFail, "sidecar '" + record.sidecar_path + "': " + why);
    return settle();
  }

  // 1. Which page: the one most of the sheet's detected IDs belong to.
  const DetectionResult result = detector.Detect(bgr, PixelOrder::kBgr);
  std::vector<const Detection*> mine;
  for (const Detection& d : result.detections)
    if (d.family == record.family.get()) mine.push_back(&d);
  r.page = ChoosePage(record, mine);
  if (r.page < 0) {
    r.undecoded = Undecoded(bgr, result, record);
    Add(&page_findings, Grade::kFail, NoPageProblem(record, result, options, &r));
    return settle();
  }
  std::vector<PlacedTag> tags;
  for (const PlacedTag& t : record.tags)
    if (t.page == r.page) tags.push_back(t);

  // 2. One fit from page millimetres over every paired tag's corners.
  std::vector<std::array<cv::Point2d, 4>> fit_corners;
  for (const Detection* d : mine) {
    std::array<cv::Point2d, 4> q;
    for (int c = 0; c < 4; ++c) q[c] = space.FromImage(d->corners[c]);
    fit_corners.push_back(q);
  }
  const std::vector<Pair> pairs = PairByIds(tags, mine);
  const auto fit = pairs.empty()
                       ? std::nullopt
                       : FitPage(tags, fit_corners, pairs, r.scan, options.max_position_error_mm);
  if (!fit) {
    Add(&page_findings, Grade::kFail, "the found tags do not fit the sheet's layout");
    return settle();
  }
  r.image_from_page = space.PixelsFromFit() * fit->image_from_page;
  r.tags_in_fit = static_cast<int>(fit->kept.size());
  r.rms_mm = fit->rms_mm;

  // 3. The page's geometry: a scan's scale, a photo's aspect.
  if (r.scan) {
    MeasureScale(*fit, &r);
  } else {
    std::vector<cv::Point2d> page, fitted;
    for (int kept : fit->kept) {
      for (int c = 0; c < 4; ++c) {
        const auto& mm = tags[pairs[kept].tag].corners_mm[c];
        page.emplace_back(mm[0], mm[1]);
        fitted.push_back(fit_corners[pairs[kept].detection][c]);
      }
    }
    MeasureAspect(page, fitted, options.camera, bgr.size(), &r);
  }

  // 4. Every tag of the page: the detection lying on it (its centre within
  // half a tag of the tag's, on the page), else where the fit puts it.
  const cv::Matx33d page_from_fit = fit->image_from_page.inv();
  auto on_page = [&](const std::array<cv::Point2d, 4>& fitted) {
    return Apply(page_from_fit, Centre(fitted));
  };
  std::vector<int> owner(mine.size(), -1);
  for (size_t k = 0; k < mine.size(); ++k) {
    const cv::Point2d c = on_page(fit_corners[k]);
    double best = 0.5 * record.tag_size_mm;
    for (size_t i = 0; i < tags.size(); ++i) {
      const double dist = std::hypot(c.x - tags[i].center_mm[0], c.y - tags[i].center_mm[1]);
      if (dist < best) best = dist, owner[k] = static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < tags.size(); ++i) {
    PrintTagResult t;
    t.expected = tags[i];
    int found = -1;
    for (size_t k = 0; k < mine.size(); ++k) {
      if (owner[k] != static_cast<int>(i)) continue;
      if (found < 0 || (mine[k]->id == tags[i].id && mine[found]->id != tags[i].id))
        found = static_cast<int>(k);
    }
    std::vector<cv::Point2d> predicted;
    for (int c = 0; c < 4; ++c)
      predicted.push_back(
          Apply(fit->image_from_page, {tags[i].corners_mm[c][0], tags[i].corners_mm[c][1]}));
    predicted = space.ToImage(predicted);
    std::copy(predicted.begin(), predicted.end(), t.corners_px.begin());
    double size_allowance = 0.0;
    if (found >= 0) {
      const Detection& d = *mine[found];
      t.found = true;
      t.found_id = d.id;
      t.hamming = d.hamming;
      t.margin = d.decision_margin;
      if (d.id == tags[i].id) {
        t.corners_px = d.corners;
        ++r.tags_found;
        const auto pair = std::find_if(pairs.begin(), pairs.end(),
                                       [&](const Pair& p) { return p.detection == found; });
        if (pair != pairs.end()) {
          t.position_error_mm = LeaveOneOutError(tags, fit_corners, pairs, *fit,
                                                 static_cast<int>(pair - pairs.begin()), r.scan);
        }
        if (r.scan) {
          const auto& q = fit_corners[found];
          t.size_mm = (cv::norm(q[1] - q[0]) + cv::norm(q[2] - q[1]) + cv::norm(q[3] - q[2]) +
                       cv::norm(q[0] - q[3])) /
                      4.0;
          const double px_per_mm = (image.dpi_x + image.dpi_y) / 2 / kMmPerInch;
          size_allowance = 1.0 / std::max(1.0, t.size_mm * px_per_mm);
        }
      }
    }
    const auto cells = ReadTagCells(bgr, t.corners_px, *record.family, record.quiet_zone_cells,
                                    record.family->CodeOf(tags[i].id));
    if (cells) t.colours = ShadesOf(*cells);
    JudgeTag(options, record, r.scan, size_allowance, &t);
    r.tags.push_back(std::move(t));
  }
  for (size_t k = 0; k < mine.size(); ++k) {
    if (owner[k] >= 0) continue;
    const cv::Point2d c = on_page(fit_corners[k]);
    r.unexpected.push_back(
        {r.page, mine[k]->family->name(), mine[k]->id, {c.x, c.y}, mine[k]->hamming == 0});
  }
  for (const Detection& d : result.detections) {
    if (d.family == record.family.get()) continue;
    std::array<cv::Point2d, 4> q;
    for (int c = 0; c < 4; ++c) q[c] = space.FromImage(d.corners[c]);
    const cv::Point2d c = on_page(q);
    r.unexpected.push_back({r.page, d.family->name(), d.id, {c.x, c.y}});
  }

  // 5. The page's verdict, and its view for the report.
  JudgePage(options, record, &r, &page_findings);
  if (r.scan && image.dpi_from_file &&
      (std::abs(r.scale_x - 1.0) > 0.2 || std::abs(r.scale_y - 1.0) > 0.2)) {
    Add(&page_findings, Grade::kFail,
        Format("the file records %.0f x %.0f dpi: if the scanner used another resolution, give "
               "it with --scan-dpi",
               image.dpi_x, image.dpi_y));
  }
  const double max_side = std::max(record.page.width_mm, record.page.height_mm);
  r.view_px_per_mm = std::min(3.0, 4000.0 / max_side);
  r.page_view = PageView(bgr, fit->image_from_page, space, record.page, r.view_px_per_mm);
  return settle();
}

}  // namespace chromatag
