// The drawn report of `verify --print` (print_check.h): per image, the page
// as the scan or photo shows it, each tag marked pass, warn or fail, and the
// page's numbers and problems.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "chromatag/generator/cairo_util.h"
#include "chromatag/verify/print_check.h"
#include "print_internal.h"

namespace chromatag {
namespace {

// One report page, in points: A4 portrait.
constexpr double kWidth = 595.0, kHeight = 842.0, kMargin = 36.0;
constexpr double kViewTop = 120.0, kViewHeight = 500.0;
constexpr int kMaxProblemLines = 14;

void SetGrade(cairo_t* cr, Grade grade, double alpha = 1.0) {
  switch (grade) {
    case Grade::kPass:
      cairo_set_source_rgba(cr, 0.10, 0.60, 0.20, alpha);
      break;
    case Grade::kWarn:
      cairo_set_source_rgba(cr, 0.90, 0.55, 0.00, alpha);
      break;
    case Grade::kFail:
      cairo_set_source_rgba(cr, 0.85, 0.10, 0.10, alpha);
      break;
  }
}

using internal::Format;

// Cuts `text` to what fits `width` points at `size`.
std::string Fit(cairo_t* cr, std::string text, double size, double width) {
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  if (e.x_advance <= width) return text;
  while (!text.empty()) {
    text.pop_back();
    // Never cut inside a UTF-8 sequence.
    while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80)
      text.pop_back();
    if (!text.empty()) text.pop_back();
    cairo_text_extents(cr, (text + "...").c_str(), &e);
    if (e.x_advance <= width) return text + "...";
  }
  return text;
}

// Splits `text` at spaces into lines that fit `width` points at `size`.
std::vector<std::string> Wrap(cairo_t* cr, const std::string& text, double size, double width) {
  cairo_set_font_size(cr, size);
  std::vector<std::string> lines;
  std::string line;
  size_t at = 0;
  while (at < text.size()) {
    const size_t space = text.find(' ', at);
    const std::string word =
        text.substr(at, space == std::string::npos ? std::string::npos : space - at);
    at = space == std::string::npos ? text.size() : space + 1;
    const std::string longer = line.empty() ? word : line + " " + word;
    cairo_text_extents_t e;
    cairo_text_extents(cr, longer.c_str(), &e);
    if (e.x_advance > width && !line.empty()) {
      lines.push_back(line);
      line = word;
    } else {
      line = longer;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

void Line(cairo_t* cr, double y, double size, const std::string& text, bool bold = false) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  DrawText(cr, kMargin, y, size,
           Fit(cr, internal::Utf8OrReplaced(text), size, kWidth - 2 * kMargin), bold);
}

std::string PageLine(const SheetRecord& record, const PrintPageResult& r) {
  if (r.page < 0) return "Page: not recognised";
  std::string line = "Page " + std::to_string(r.page + 1) + " of " +
                     std::to_string(record.num_pages) + ": " + std::to_string(r.tags_found) +
                     " of " + std::to_string(r.tags.size()) + " tags found";
  if (r.scan) {
    line += Format(", scan at %.0f dpi: scale x %.3f ± %.3f, y %.3f ± %.3f", r.dpi_x, r.scale_x,
                   std::max(0.001, 2 * r.scale_x_error), r.scale_y,
                   std::max(0.001, 2 * r.scale_y_error));
  } else if (r.aspect > 0) {
    line += Format(", photo: aspect x/y %.3f ± %.3f (size not measurable in a photo)", r.aspect,
                   std::max(0.001, 2 * r.aspect_error));
  } else {
    line += ", photo: too few tags to judge the aspect";
  }
  return line;
}

// Draws the page view into the box and marks each tag.
void DrawPage(cairo_t* cr, const SheetRecord& record, const PrintPageResult& r) {
  const double box_w = kWidth - 2 * kMargin;
  const double view_px_per_mm = r.view_px_per_mm > 0 ? r.view_px_per_mm : 1.0;
  const double scale =
      std::min(box_w / record.page.width_mm, kViewHeight / record.page.height_mm);  // pt per mm
  const double x0 = kMargin + (box_w - record.page.width_mm * scale) / 2, y0 = kViewTop;
  cairo_save(cr);
  cairo_translate(cr, x0, y0);
  if (!r.page_view.empty()) {
    // The page as seen, faded so that the marks read.
    cv::Mat bgra;
    cv::cvtColor(r.page_view, bgra, cv::COLOR_BGR2BGRA);
    cairo_surface_t* image = cairo_image_surface_create(CAIRO_FORMAT_RGB24, bgra.cols, bgra.rows);
    if (cairo_surface_status(image) == CAIRO_STATUS_SUCCESS) {
      cairo_surface_flush(image);
      unsigned char* data = cairo_image_surface_get_data(image);
      const int stride = cairo_image_surface_get_stride(image);
      for (int y = 0; y < bgra.rows; ++y)
        std::copy_n(bgra.ptr<unsigned char>(y), 4 * bgra.cols, data + y * stride);
      cairo_surface_mark_dirty(image);
      cairo_save(cr);
      const double s = scale / view_px_per_mm;
      cairo_scale(cr, s, s);
      cairo_set_source_surface(cr, image, 0, 0);
      cairo_paint_with_alpha(cr, 0.55);
      cairo_restore(cr);
    }
    cairo_surface_destroy(image);
  } else {
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_rectangle(cr, 0, 0, record.page.width_mm * scale, record.page.height_mm * scale);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  cairo_set_line_width(cr, 0.8);
  cairo_rectangle(cr, 0, 0, record.page.width_mm * scale, record.page.height_mm * scale);
  cairo_stroke(cr);
  for (const PrintTagResult& t : r.tags) {
    SetGrade(cr, t.grade);
    cairo_set_line_width(cr, t.grade == Grade::kPass ? 1.5 : 3.0);
    for (int c = 0; c < 4; ++c) {
      const auto& p = t.expected.corners_mm[c];
      if (c == 0)
        cairo_move_to(cr, p[0] * scale, p[1] * scale);
      else
        cairo_line_to(cr, p[0] * scale, p[1] * scale);
    }
    cairo_close_path(cr);
    cairo_stroke(cr);
    const double size = std::clamp(record.tag_size_mm * scale * 0.22, 5.0, 10.0);
    const std::string label = "ID " + std::to_string(t.expected.id) + " " + GradeName(t.grade);
    DrawText(cr, t.expected.corners_mm[3][0] * scale,
             t.expected.corners_mm[3][1] * scale + size + 1.0, size, label, true);
  }
  cairo_restore(cr);
}

void DrawReportPage(cairo_t* cr, const SheetRecord& record, const PrintPageResult& r) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  Line(cr, kMargin + 12, 14, "ChromaTag print check: " + r.image, true);
  Line(cr, kMargin + 32, 9,
       "Sheet: " + record.family->name() + ", " + std::to_string(record.tags.size()) + " tags of " +
           Format("%.1f", record.tag_size_mm) + " mm, palette " + record.palette.name + ", " +
           record.page.name);
  Line(cr, kMargin + 46, 9, PageLine(record, r));
  SetGrade(cr, r.grade);
  DrawText(cr, kMargin, kMargin + 66, 12, std::string("Verdict: ") + GradeName(r.grade), true);
  DrawPage(cr, record, r);
  // Problems: the page's first, then each tag's worst.
  std::vector<std::pair<Grade, std::string>> lines;
  for (size_t i = 0; i < r.problems.size(); ++i)
    lines.push_back({r.problem_grades[i], "page: " + r.problems[i]});
  for (const PrintTagResult& t : r.tags) {
    for (size_t i = 0; i < t.problems.size(); ++i) {
      lines.push_back(
          {t.problem_grades[i], "ID " + std::to_string(t.expected.id) + ": " + t.problems[i]});
    }
  }
  double y = kViewTop + kViewHeight + 28;
  int shown = 0;
  for (const auto& [grade, text] : lines) {
    if (shown == kMaxProblemLines) {
      Line(cr, y, 8, "... " + std::to_string(lines.size() - shown) + " more (see the text report)");
      break;
    }
    SetGrade(cr, grade);
    cairo_rectangle(cr, kMargin, y - 6, 6, 6);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    const double width = kWidth - 2 * kMargin - 10;
    const auto wrapped = Wrap(cr, internal::Utf8OrReplaced(text), 8, width);
    for (size_t i = 0; i < wrapped.size() && i < 3; ++i) {
      DrawText(cr, kMargin + 10, y, 8, Fit(cr, wrapped[i], 8, width));
      y += 10;
    }
    y += 2;
    ++shown;
  }
  if (lines.empty()) Line(cr, y, 9, "Every tag passes.");
}

}  // namespace

std::string RenderPrintReportPdf(const SheetRecord& record, const PrintVerdict& verdict) {
  return RenderPdf(
      kWidth, kHeight, "ChromaTag print check", static_cast<int>(verdict.images.size()),
      [&](cairo_t* cr, int page) { DrawReportPage(cr, record, verdict.images[page]); });
}

std::string RenderPrintReportPng(const SheetRecord& record, const PrintVerdict& verdict) {
  constexpr double kScale = 1.5;  // 108 dpi.
  constexpr int kPerRow = 4;
  if (static_cast<int>(verdict.images.size()) > kMaxPngReportImages) return "";
  const int page_w = static_cast<int>(kWidth * kScale), page_h = static_cast<int>(kHeight * kScale);
  const int n = std::max<int>(1, static_cast<int>(verdict.images.size()));
  const int columns = std::min(n, kPerRow), rows = (n + kPerRow - 1) / kPerRow;
  return RenderPng(page_w * columns, page_h * rows, 72.0 * kScale, [&](cairo_t* cr) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (size_t i = 0; i < verdict.images.size(); ++i) {
      cairo_save(cr);
      cairo_translate(cr, static_cast<double>(i % kPerRow) * page_w,
                      static_cast<double>(i / kPerRow) * page_h);
      cairo_scale(cr, kScale, kScale);
      cairo_rectangle(cr, 0, 0, kWidth, kHeight);
      cairo_clip(cr);
      DrawReportPage(cr, record, verdict.images[i]);
      cairo_restore(cr);
    }
  });
}

}  // namespace chromatag
