#include "chromatag/calib/camera_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "chromatag/families/version.h"
#include "chromatag/generator/cairo_util.h"

namespace chromatag {
namespace {

// A4 landscape in points.
constexpr double kWidth = 842, kHeight = 595;
constexpr double kMargin = 28;

std::string F(const char* format, double a, double b = 0, double c = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c);
  return text;
}

void Text(cairo_t* cr, double x, double y, double size, const std::string& text, bool bold = false,
          double grey = 0.0) {
  cairo_set_source_rgb(cr, grey, grey, grey);
  DrawText(cr, x, y, size, text, bold);
}

// A colour per view, around the hue circle.
void ViewColour(cairo_t* cr, int view, double alpha = 1.0) {
  const double h = std::fmod(view * 0.618034, 1.0) * 6;
  const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0:
      r = 1, g = x;
      break;
    case 1:
      r = x, g = 1;
      break;
    case 2:
      g = 1, b = x;
      break;
    case 3:
      g = x, b = 1;
      break;
    case 4:
      r = x, b = 1;
      break;
    default:
      r = 1, b = x;
      break;
  }
  cairo_set_source_rgba(cr, 0.8 * r, 0.8 * g, 0.8 * b, alpha);
}

// `text` cut into lines of at most `width` characters at spaces.
std::vector<std::string> Wrap(const std::string& text, size_t width) {
  std::vector<std::string> lines;
  std::string line;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      lines.push_back(line);
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

// The image's frame at (x, y), `width` wide; returns the scale.
double ImageFrame(cairo_t* cr, const CameraCalibration& c, double x, double y, double width,
                  const std::string& caption) {
  const double s = width / c.image_size.width;
  cairo_set_source_rgb(cr, 0.96, 0.96, 0.96);
  cairo_rectangle(cr, x, y, width, c.image_size.height * s);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.5, 0.5, 0.5);
  cairo_set_line_width(cr, 0.6);
  cairo_stroke(cr);
  Text(cr, x, y - 5, 8.5, caption, true);
  return s;
}

void DrawCoverage(cairo_t* cr, const CameraCalibration& c, double x, double y, double width) {
  const double s = ImageFrame(
      cr, c, x, y, width,
      F("Coverage: %.0f corners in %.0f views", c.corners_used,
        std::count_if(c.views.begin(), c.views.end(), [](const auto& v) { return v.used; })));
  for (size_t v = 0; v < c.views.size(); ++v) {
    ViewColour(cr, static_cast<int>(v), 0.8);
    for (const cv::Point2d& p : c.views[v].corners) {
      cairo_arc(cr, x + p.x * s, y + p.y * s, 0.9, 0, 2 * M_PI);
      cairo_fill(cr);
    }
  }
}

double LargestResidual(const CameraCalibration& c) {
  double largest = 1e-3;
  for (const auto& v : c.views)
    for (const cv::Point2d& e : v.residuals) largest = std::max(largest, cv::norm(e));
  return largest;
}

void DrawResidualVectors(cairo_t* cr, const CameraCalibration& c, double x, double y,
                         double width) {
  // The largest residual drawn 18 points long.
  const double gain = 18.0 / LargestResidual(c);
  const double s =
      ImageFrame(cr, c, x, y, width,
                 F("Residuals where they lie, drawn %.0fx", gain / (width / c.image_size.width)));
  cairo_set_line_width(cr, 0.5);
  for (size_t v = 0; v < c.views.size(); ++v) {
    ViewColour(cr, static_cast<int>(v));
    for (size_t i = 0; i < c.views[v].corners.size(); ++i) {
      const cv::Point2d p = c.views[v].corners[i];
      const cv::Point2d e = c.views[v].residuals[i];
      cairo_move_to(cr, x + p.x * s, y + p.y * s);
      cairo_rel_line_to(cr, e.x * gain, e.y * gain);
      cairo_stroke(cr);
    }
  }
}

void DrawScatter(cairo_t* cr, const CameraCalibration& c, double x, double y, double side) {
  const double reach = std::max(0.1, std::ceil(LargestResidual(c) * 10) / 10);
  const double s = 0.5 * side / reach;
  Text(cr, x, y - 5, 8.5, F("Residuals (px), rms %.3f", c.rms_px), true);
  cairo_set_source_rgb(cr, 0.96, 0.96, 0.96);
  cairo_rectangle(cr, x, y, side, side);
  cairo_fill(cr);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 0.5);
  cairo_move_to(cr, x + side / 2, y);
  cairo_rel_line_to(cr, 0, side);
  cairo_move_to(cr, x, y + side / 2);
  cairo_rel_line_to(cr, side, 0);
  cairo_stroke(cr);
  cairo_arc(cr, x + side / 2, y + side / 2, c.rms_px * s, 0, 2 * M_PI);
  cairo_stroke(cr);
  for (size_t v = 0; v < c.views.size(); ++v) {
    ViewColour(cr, static_cast<int>(v), 0.7);
    for (const cv::Point2d& e : c.views[v].residuals) {
      cairo_arc(cr, x + side / 2 + e.x * s, y + side / 2 + e.y * s, 0.8, 0, 2 * M_PI);
      cairo_fill(cr);
    }
  }
  Text(cr, x, y + side + 10, 7, F("-%.1f", reach), false, 0.3);
  Text(cr, x + side - 14, y + side + 10, 7, F("+%.1f", reach), false, 0.3);
  Text(cr, x + side / 2 + 3, y + side + 10, 7, "circle: rms", false, 0.3);
}

// Per-view rms bars; returns the y below the chart.
double DrawViewBars(cairo_t* cr, const CameraCalibration& c, double x, double y, double width,
                    double height) {
  double largest = 0.05;
  for (const auto& v : c.views) largest = std::max(largest, v.rms_px);
  Text(cr, x, y - 5, 8.5, "Rms of every view (px); left-out views empty", true);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 0.5);
  cairo_move_to(cr, x, y);
  cairo_rel_line_to(cr, 0, height);
  cairo_rel_line_to(cr, width, 0);
  cairo_stroke(cr);
  const double bar = width / std::max<size_t>(1, c.views.size());
  for (size_t v = 0; v < c.views.size(); ++v) {
    const double h = c.views[v].rms_px / largest * (height - 2);
    if (c.views[v].used) {
      ViewColour(cr, static_cast<int>(v));
      cairo_rectangle(cr, x + v * bar + 0.15 * bar, y + height - h, 0.7 * bar, h);
      cairo_fill(cr);
    } else {
      cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
      cairo_rectangle(cr, x + v * bar + 0.15 * bar, y + height - 4, 0.7 * bar, 4);
      cairo_stroke(cr);
    }
  }
  Text(cr, x - 22, y + 7, 7, F("%.2f", largest), false, 0.3);
  Text(cr, x, y + height + 9, 7, "view 1", false, 0.3);
  Text(cr, x + width - 30, y + height + 9, 7, F("view %.0f", c.views.size()), false, 0.3);
  return y + height + 12;
}

// The fitted parameters with their standard deviations, from `y` down;
// returns the y below them.
double DrawParameters(cairo_t* cr, const CameraCalibration& c, double y) {
  Text(cr, kMargin, y, 9.5, "Parameters (one standard deviation)", true);
  y += 14;
  const std::vector<std::string> names = CalibrationParameterNames(c.camera);
  std::vector<double> values = {c.camera.fx, c.camera.fy, c.camera.cx, c.camera.cy};
  values.insert(values.end(), c.camera.distortion.begin(), c.camera.distortion.end());
  for (size_t i = 0; i < names.size() && i < values.size(); ++i) {
    Text(cr, kMargin, y, 8.5, names[i]);
    const bool pixels = i < 4;
    // A coefficient held at 0 (k3 unless asked for) has no deviation.
    const bool fixed = !pixels && i < c.std_dev.size() && c.std_dev[i] == 0.0 && values[i] == 0.0;
    Text(cr, kMargin + 30, y, 8.5,
         F(pixels ? "%10.2f" : "%10.5f", values[i]) +
             (fixed                  ? std::string("  (not fitted)")
              : i < c.std_dev.size() ? F(pixels ? "  +- %.2f px" : "  +- %.5f", c.std_dev[i])
                                     : std::string()));
    y += 11;
  }
  return y;
}

// The doubts and warnings, from `y` down; returns the y below them.
double DrawWarnings(cairo_t* cr, const CameraCalibration& c, double y) {
  // The parameters in doubt first, then what the views leave weak.
  std::vector<std::string> warnings = c.doubts;
  warnings.insert(warnings.end(), c.warnings.begin(), c.warnings.end());
  Text(cr, kMargin, y, 9.5, warnings.empty() ? "No warnings" : "Warnings", true);
  y += 12;
  for (const std::string& w : warnings) {
    for (const std::string& line : Wrap(w, 62)) {
      Text(cr, kMargin, y, 7.5, line, false, 0.15);
      y += 9.5;
    }
    y += 3;
  }
  return y;
}

// The views and tags left out and why, from `y` down to the page's foot.
void DrawLeftOut(cairo_t* cr, const CameraCalibration& c, double y) {
  std::vector<std::string> left_out;
  for (const CalibrationViewResult& view : c.views) {
    if (!view.used) left_out.push_back(view.name + ": " + view.why_not);
    for (size_t t = 0; t < view.tags_left_out.size(); ++t)
      left_out.push_back(view.name + ", ID " + std::to_string(view.tags_left_out[t]) + ": " +
                         (t < view.why_left_out.size() ? view.why_left_out[t] : ""));
  }
  Text(cr, kMargin, y, 9.5, left_out.empty() ? "Nothing left out" : "Left out", true);
  y += 12;
  for (size_t i = 0; i < left_out.size(); ++i) {
    if (y + 20 >= kHeight - kMargin && i + 1 < left_out.size()) {
      Text(cr, kMargin, y, 7.5, F("... and %.0f more", left_out.size() - i), false, 0.15);
      break;
    }
    const std::vector<std::string> lines = Wrap(left_out[i], 72);
    for (size_t l = 0; l < lines.size(); ++l) {
      Text(cr, kMargin + (l ? 8 : 0), y, 7.5, lines[l], false, 0.15);
      y += 9.5;
    }
  }
}

void DrawReport(cairo_t* cr, const CameraCalibration& c, const std::string& title) {
  // The page's own rectangle, not cairo_paint: the PNG draws the pages one
  // below the other on one surface.
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, kWidth, kHeight);
  cairo_fill(cr);
  double y = kMargin + 12;
  Text(cr, kMargin, y, 14, "Camera calibration: " + title, true);
  y += 16;
  int used = 0;
  for (const auto& v : c.views) used += v.used ? 1 : 0;
  Text(cr, kMargin, y, 8.5,
       std::string(LensModelName(c.camera.model)) + " model, " +
           F("%.0f x %.0f pixels, ", c.image_size.width, c.image_size.height) +
           F("%.0f of %.0f views used, ", used, c.views.size()) +
           F("reprojection rms %.3f px. chromatag ", c.rms_px) + kVersion,
       false, 0.25);
  // Left column: parameters, warnings, left-out views.
  y += 22;
  y = DrawParameters(cr, c, y);
  y += 8;
  y = DrawWarnings(cr, c, y);
  y += 6;
  DrawLeftOut(cr, c, y);
  // Right: two image panels, the scatter and the bars.
  // The image panels at most 236 points wide and 236 high, so that a
  // portrait frame leaves room for the plots below.
  const double right = 330, gap = 22, top = kMargin + 70;
  const double aspect = static_cast<double>(c.image_size.height) / c.image_size.width;
  const double panel = std::min(236.0, 236.0 / aspect);
  DrawCoverage(cr, c, right, top, panel);
  DrawResidualVectors(cr, c, right + 236.0 + gap, top, panel);
  const double below = top + panel * aspect + 34;
  const double side = std::max(100.0, std::min(170.0, kHeight - kMargin - below - 14));
  DrawScatter(cr, c, right, below, side);
  DrawViewBars(cr, c, right + side + 40, below, kWidth - kMargin - (right + side + 40), side);
}

// A map's value as a colour: green at 0, yellow at `limit`, red from twice
// it; grey where nothing is known.
void MapColour(cairo_t* cr, double value, double limit) {
  if (!std::isfinite(value)) {
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    return;
  }
  const double t = std::clamp(value / (2 * limit), 0.0, 1.0);
  if (t < 0.5) {
    cairo_set_source_rgb(cr, 0.3 + 1.3 * t, 0.75, 0.3);
  } else {
    cairo_set_source_rgb(cr, 0.95, 0.75 - 1.2 * (t - 0.5), 0.3 - 0.4 * (t - 0.5));
  }
}

// One ProjectionCheck map over the image's frame, the central 80 % outlined,
// each cell's value printed when the cells are large enough.
void DrawMap(cairo_t* cr, const CameraCalibration& c, const std::vector<double>& map, double x,
             double y, double width, const std::string& caption, double limit) {
  const double s = ImageFrame(cr, c, x, y, width, caption);
  const cv::Size grid = c.projection.grid;
  if (map.size() != static_cast<size_t>(grid.area())) {
    Text(cr, x + 8, y + 20, 9, "not measured (fewer than six views)", false, 0.3);
    return;
  }
  const double cw = c.image_size.width * s / grid.width, ch = c.image_size.height * s / grid.height;
  for (int r = 0; r < grid.height; ++r) {
    for (int col = 0; col < grid.width; ++col) {
      MapColour(cr, map[r * grid.width + col], limit);
      cairo_rectangle(cr, x + col * cw, y + r * ch, cw + 0.2, ch + 0.2);
      cairo_fill(cr);
    }
  }
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_set_line_width(cr, 0.8);
  cairo_rectangle(cr, x + 0.1 * c.image_size.width * s, y + 0.1 * c.image_size.height * s,
                  0.8 * c.image_size.width * s, 0.8 * c.image_size.height * s);
  cairo_stroke(cr);
}

void DrawLegend(cairo_t* cr, double x, double y, double width, double limit) {
  for (int i = 0; i < 100; ++i) {
    MapColour(cr, 2 * limit * i / 99.0, limit);
    cairo_rectangle(cr, x + width * i / 100.0, y, width / 100.0 + 0.3, 8);
    cairo_fill(cr);
  }
  Text(cr, x, y + 19, 8, "0 px", false, 0.25);
  Text(cr, x + 0.5 * width - 14, y + 19, 8, F("%.1f px (limit)", limit), false, 0.25);
  Text(cr, x + width - 40, y + 19, 8, F("%.1f px +", 2 * limit), false, 0.25);
}

// Page 2: the projection check's two maps and figures.
void DrawProjectionPage(cairo_t* cr, const CameraCalibration& c, const std::string& title) {
  // The page's own rectangle, not cairo_paint: the PNG draws the pages one
  // below the other on one surface.
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, kWidth, kHeight);
  cairo_fill(cr);
  const ProjectionCheck& p = c.projection;
  double y = kMargin + 12;
  Text(cr, kMargin, y, 14, "How well the model projects: " + title, true);
  y += 16;
  Text(cr, kMargin, y, 8.5,
       F("At %.3g m from the camera. Outlined: the central 80 %% of the image, where the limits "
         "(%.1f px) apply.",
         p.distance, kMaxProjectionUncertaintyPx),
       false, 0.25);
  const double panel = 370, top = y + 40;
  const double aspect = static_cast<double>(c.image_size.height) / c.image_size.width;
  const double width = std::min(panel, 360.0 / aspect);
  DrawMap(cr, c, p.uncertainty_px, kMargin, top, width,
          F("Projection uncertainty (1 sigma): median %.3f, worst %.3f px", p.uncertainty_median_px,
            p.uncertainty_worst_px),
          kMaxProjectionUncertaintyPx);
  DrawMap(cr, c, p.cross_validation_px, kMargin + panel + 30, top, width,
          p.cross_validation_px.empty()
              ? std::string("Cross-validation: two halves of the views")
              : F("Cross-validation, two halves of the views: median %.3f, worst %.3f px",
                  p.cross_validation_median_px, p.cross_validation_worst_px),
          kMaxCrossValidationPx);
  DrawLegend(cr, kMargin, top + width * aspect + 18, 240, kMaxProjectionUncertaintyPx);
}

}  // namespace

std::string RenderCameraReportPdf(const CameraCalibration& calibration, const std::string& title) {
  return RenderPdf(kWidth, kHeight, "ChromaTag camera calibration report", 2,
                   [&](cairo_t* cr, int page) {
                     if (page == 0) {
                       DrawReport(cr, calibration, title);
                     } else {
                       DrawProjectionPage(cr, calibration, title);
                     }
                   });
}

std::string RenderCameraReportPng(const CameraCalibration& calibration, const std::string& title,
                                  double scale) {
  const int width = static_cast<int>(std::lround(kWidth * scale));
  // Both pages, one below the other.
  const int height = static_cast<int>(std::lround(2 * kHeight * scale));
  return RenderPng(width, height, 0, [&](cairo_t* cr) {
    cairo_scale(cr, scale, scale);
    DrawReport(cr, calibration, title);
    cairo_translate(cr, 0, kHeight);
    DrawProjectionPage(cr, calibration, title);
  });
}

}  // namespace chromatag
