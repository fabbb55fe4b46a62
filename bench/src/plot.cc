#include "chromatag/bench/plot.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "chromatag/families/color.h"

namespace chromatag::bench {
namespace {

constexpr int kWidth = 720, kHeight = 480;
constexpr double kLeft = 70, kRight = 170, kTop = 44, kBottom = 60;

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

// A white kWidth x kHeight image and a context drawing on it.
struct Canvas {
  Surface surface{cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, kHeight),
                  &cairo_surface_destroy};
  Context context{cairo_create(surface.get()), &cairo_destroy};
  Canvas() {
    cairo_set_source_rgb(context.get(), 1, 1, 1);
    cairo_paint(context.get());
  }
};

std::string Format(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void Text(cairo_t* cr, const std::string& text, double x, double y, double size, double align_x,
          double align_y, bool bold = false) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  cairo_move_to(cr, x - extents.x_bearing - align_x * extents.width,
                y - extents.y_bearing - align_y * extents.height);
  cairo_show_text(cr, text.c_str());
}

void VerticalText(cairo_t* cr, const std::string& text, double x, double y, double size) {
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, -kPi / 2);
  Text(cr, text, 0, 0, size, 0.5, 0.5);
  cairo_restore(cr);
}

struct Frame {
  double x0, x1, y0, y1;  // Data range.
  double Px(double x) const { return kLeft + (x - x0) / (x1 - x0) * (kWidth - kLeft - kRight); }
  double Py(double y) const {
    return kHeight - kBottom - (y - y0) / (y1 - y0) * (kHeight - kTop - kBottom);
  }
};

void Labels(cairo_t* cr, const std::string& title, const std::string& x_label,
            const std::string& y_label) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  Text(cr, title, (kLeft + kWidth - kRight) / 2, 14, 16, 0.5, 0.0, true);
  Text(cr, x_label, (kLeft + kWidth - kRight) / 2, kHeight - 22, 13, 0.5, 0.0);
  VerticalText(cr, y_label, 20, (kTop + kHeight - kBottom) / 2, 13);
}

bool Finish(cairo_surface_t* surface, const std::string& path, std::string* error) {
  cairo_surface_flush(surface);
  const cairo_status_t status = cairo_surface_write_to_png(surface, path.c_str());
  if (status != CAIRO_STATUS_SUCCESS) {
    if (error) *error = "cannot write " + path + ": " + cairo_status_to_string(status);
    return false;
  }
  return true;
}

}  // namespace

std::array<double, 3> ScaleColor(double value) {
  // Piecewise linear through dark blue, teal, green and yellow.
  static const double kStops[][3] = {
      {0.19, 0.07, 0.45}, {0.13, 0.40, 0.56}, {0.16, 0.66, 0.47}, {0.99, 0.88, 0.15}};
  const double t = std::clamp(value, 0.0, 1.0) * 3.0;
  const int i = std::min(2, static_cast<int>(t));
  const double f = t - i;
  return {kStops[i][0] + f * (kStops[i + 1][0] - kStops[i][0]),
          kStops[i][1] + f * (kStops[i + 1][1] - kStops[i][1]),
          kStops[i][2] + f * (kStops[i + 1][2] - kStops[i][2])};
}

bool WriteLinePlot(const LinePlot& plot, const std::string& png_path, std::string* error) {
  Canvas canvas;
  cairo_t* cr = canvas.context.get();
  const Frame f{plot.x_min, plot.x_max, plot.y_min, plot.y_max};

  // Grid and tick labels.
  cairo_set_line_width(cr, 1.0);
  for (double x = plot.x_min; x <= plot.x_max + 1e-9; x += plot.x_tick) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, f.Px(x), f.Py(plot.y_min));
    cairo_line_to(cr, f.Px(x), f.Py(plot.y_max));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    Text(cr, Format(x), f.Px(x), f.Py(plot.y_min) + 6, 11, 0.5, 0.0);
  }
  for (double y = plot.y_min; y <= plot.y_max + 1e-9; y += plot.y_tick) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, f.Px(plot.x_min), f.Py(y));
    cairo_line_to(cr, f.Px(plot.x_max), f.Py(y));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    Text(cr, Format(y), f.Px(plot.x_min) - 6, f.Py(y), 11, 1.0, 0.5);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, f.Px(plot.x_min), f.Py(plot.y_max), f.Px(plot.x_max) - f.Px(plot.x_min),
                  f.Py(plot.y_min) - f.Py(plot.y_max));
  cairo_stroke(cr);

  // Lines with a dot at each point, and the legend on the right.
  for (size_t s = 0; s < plot.series.size(); ++s) {
    const Series& series = plot.series[s];
    cairo_set_source_rgb(cr, series.rgb[0], series.rgb[1], series.rgb[2]);
    cairo_set_line_width(cr, 2.2);
    bool drawing = false;
    for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
      if (std::isnan(series.y[i])) {
        if (drawing) cairo_stroke(cr);
        drawing = false;
        continue;
      }
      const double px = f.Px(series.x[i]), py = f.Py(series.y[i]);
      drawing ? cairo_line_to(cr, px, py) : cairo_move_to(cr, px, py);
      drawing = true;
    }
    if (drawing) cairo_stroke(cr);
    for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
      if (std::isnan(series.y[i])) continue;
      cairo_arc(cr, f.Px(series.x[i]), f.Py(series.y[i]), 3.0, 0, 2 * kPi);
      cairo_fill(cr);
    }
    const double ly = kTop + 12 + 22.0 * s, lx = kWidth - kRight + 14;
    cairo_move_to(cr, lx, ly);
    cairo_line_to(cr, lx + 22, ly);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    Text(cr, series.name, lx + 28, ly, 12, 0.0, 0.5);
  }
  Labels(cr, plot.title, plot.x_label, plot.y_label);
  return Finish(canvas.surface.get(), png_path, error);
}

bool WriteHeatMap(const HeatMap& map, const std::string& png_path, std::string* error) {
  Canvas canvas;
  cairo_t* cr = canvas.context.get();
  if (map.x_edges.size() < 2 || map.y_edges.size() < 2) {
    if (error) *error = "a heat map needs at least one cell";
    return false;
  }
  const Frame f{map.x_edges.front(), map.x_edges.back(), map.y_edges.front(), map.y_edges.back()};
  for (size_t row = 0; row + 1 < map.y_edges.size(); ++row) {
    for (size_t col = 0; col + 1 < map.x_edges.size(); ++col) {
      const double x0 = f.Px(map.x_edges[col]), x1 = f.Px(map.x_edges[col + 1]);
      const double y0 = f.Py(map.y_edges[row + 1]), y1 = f.Py(map.y_edges[row]);
      const double value = row < map.values.size() && col < map.values[row].size()
                               ? map.values[row][col]
                               : std::nan("");
      if (std::isnan(value)) {
        cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
      } else {
        const auto c = ScaleColor(value);
        cairo_set_source_rgb(cr, c[0], c[1], c[2]);
      }
      cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
      cairo_fill(cr);
      if (!std::isnan(value)) {
        const double shade = value > 0.6 ? 0.0 : 1.0;
        cairo_set_source_rgb(cr, shade, shade, shade);
        Text(cr, Format(std::round(value * 100)), (x0 + x1) / 2, (y0 + y1) / 2 - 5, 10, 0.5, 0.5);
        if (row < map.counts.size() && col < map.counts[row].size()) {
          Text(cr, "n=" + std::to_string(map.counts[row][col]), (x0 + x1) / 2, (y0 + y1) / 2 + 7,
               7.5, 0.5, 0.5);
        }
      }
    }
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  for (double x : map.x_edges) Text(cr, Format(x), f.Px(x), f.Py(f.y0) + 6, 11, 0.5, 0.0);
  for (double y : map.y_edges) Text(cr, Format(y), f.Px(f.x0) - 6, f.Py(y), 11, 1.0, 0.5);
  // Colour scale on the right.
  const double bx = kWidth - kRight + 30, bw = 18;
  for (int i = 0; i < 100; ++i) {
    const auto c = ScaleColor(i / 99.0);
    cairo_set_source_rgb(cr, c[0], c[1], c[2]);
    const double y = f.Py(f.y0) - (i + 1) / 100.0 * (f.Py(f.y0) - f.Py(f.y1));
    cairo_rectangle(cr, bx, y, bw, (f.Py(f.y0) - f.Py(f.y1)) / 100.0 + 0.5);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  Text(cr, "recall 100 %", bx + bw + 6, f.Py(f.y1), 11, 0.0, 0.5);
  Text(cr, "0 %", bx + bw + 6, f.Py(f.y0), 11, 0.0, 0.5);
  Text(cr, "grey: no data", bx - 4, f.Py(f.y0) + 20, 10, 0.0, 0.5);
  Labels(cr, map.title, map.x_label, map.y_label);
  return Finish(canvas.surface.get(), png_path, error);
}

}  // namespace chromatag::bench
