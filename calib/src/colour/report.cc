// The calibration report (report.h).
#include "chromatag/calib/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "chromatag/base/units.h"
#include "chromatag/families/color.h"
#include "chromatag/families/version.h"
#include "chromatag/generator/cairo_util.h"

namespace chromatag {
namespace {

constexpr double kPlotX = 40, kPlotY = 92, kPlotSide = 400;
constexpr double kMapTop = 560;  // First row of per-photo maps.
constexpr double kMapWidth = 185, kMapRowHeight = 300;
constexpr int kMapsPerRow = 4;

void SetColour(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

// While ReportOverlaps runs: every label's and swatch's box, in report units.
struct Box {
  double x0, y0, x1, y1;
  std::string what;
};
thread_local std::vector<Box>* g_boxes = nullptr;

void Text(cairo_t* cr, double x, double y, double size, const std::string& text, bool bold = false,
          Rgb colour = {0, 0, 0}) {
  SetColour(cr, colour);
  DrawText(cr, x, y, size, text, bold);
  if (g_boxes && !text.empty()) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    g_boxes->push_back({x + e.x_bearing, y + e.y_bearing, x + e.x_bearing + e.width,
                        y + e.y_bearing + e.height, "'" + text + "'"});
  }
}

// A filled legend or palette swatch (its box is checked against the labels).
void Swatch(cairo_t* cr, double x, double y, double side, const Rgb& colour) {
  cairo_rectangle(cr, x, y, side, side);
  SetColour(cr, colour);
  cairo_fill(cr);
  if (g_boxes) g_boxes->push_back({x, y, x + side, y + side, "a swatch"});
}

std::string F(const char* format, double a, double b = 0, double c = 0) {
  char text[256];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

Rgb VerdictColour(Verdict v) {
  return v == Verdict::kGood   ? Rgb{0.1, 0.55, 0.2}
         : v == Verdict::kThin ? Rgb{0.85, 0.5, 0.0}
                               : Rgb{0.8, 0.1, 0.1};
}

// Marker shapes tell the photos apart: square, triangle, diamond, circle, ...
void Marker(cairo_t* cr, int photo, double x, double y, double r) {
  switch (photo % 4) {
    case 0:
      cairo_rectangle(cr, x - r, y - r, 2 * r, 2 * r);
      break;
    case 1:
      cairo_move_to(cr, x, y - 1.2 * r);
      cairo_line_to(cr, x + 1.1 * r, y + 0.8 * r);
      cairo_line_to(cr, x - 1.1 * r, y + 0.8 * r);
      cairo_close_path(cr);
      break;
    case 2:
      cairo_move_to(cr, x, y - 1.3 * r);
      cairo_line_to(cr, x + 1.3 * r, y);
      cairo_line_to(cr, x, y + 1.3 * r);
      cairo_line_to(cr, x - 1.3 * r, y);
      cairo_close_path(cr);
      break;
    default:
      cairo_new_sub_path(cr);
      cairo_arc(cr, x, y, r, 0, 2 * kPi);
      break;
  }
}

struct Plane {
  double lo = -100, hi = 100;
  double X(double a) const { return kPlotX + (a - lo) / (hi - lo) * kPlotSide; }
  double Y(double b) const { return kPlotY + kPlotSide - (b - lo) / (hi - lo) * kPlotSide; }
};

Plane PlaneFor(const CalibrationResult& r) {
  double extent = 40;
  for (const Patch& p : r.layout.patches) {
    extent = std::max({extent, std::abs(p.lab.a), std::abs(p.lab.b)});
  }
  for (const PhotoResult& photo : r.photos) {
    for (const PatchMeasurement& m : photo.measurement.patches) {
      if (m.usable()) extent = std::max({extent, std::abs(m.lab.a), std::abs(m.lab.b)});
    }
  }
  Plane plane;
  plane.hi = std::ceil((extent + 5) / 20) * 20;
  plane.lo = -plane.hi;
  return plane;
}

// The plane's grid lines every 20 units, their values and the axis names.
void DrawAxes(cairo_t* cr, const Plane& plane) {
  cairo_set_line_width(cr, 0.4);
  for (double v = plane.lo; v <= plane.hi + 1e-9; v += 20) {
    cairo_set_source_rgb(cr, v == 0 ? 0.5 : 0.85, v == 0 ? 0.5 : 0.85, v == 0 ? 0.5 : 0.85);
    cairo_move_to(cr, plane.X(v), plane.Y(plane.lo));
    cairo_line_to(cr, plane.X(v), plane.Y(plane.hi));
    cairo_move_to(cr, plane.X(plane.lo), plane.Y(v));
    cairo_line_to(cr, plane.X(plane.hi), plane.Y(v));
    cairo_stroke(cr);
    Text(cr, plane.X(v) - 6, plane.Y(plane.lo) + 11, 7, F("%.0f", v));
    Text(cr, plane.X(plane.lo) - 22, plane.Y(v) + 3, 7, F("%.0f", v));
  }
  Text(cr, plane.X(plane.hi) - 12, plane.Y(plane.lo) + 22, 9, "a*", true);
  Text(cr, plane.X(plane.lo) - 30, plane.Y(plane.hi) - 6, 9, "b*", true);
}

// Every candidate patch, as meant and as printed in each photo.
void DrawCandidates(cairo_t* cr, const CalibrationResult& r, const Plane& plane) {
  // Candidates: where they were meant to be (grey) and where they printed
  // (their own colour, every photo).
  for (const Patch& p : r.layout.patches) {
    if (p.kind != PatchKind::kCandidate) continue;
    cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
    cairo_new_sub_path(cr);
    cairo_arc(cr, plane.X(p.lab.a), plane.Y(p.lab.b), 1.2, 0, 2 * kPi);
    cairo_fill(cr);
    for (size_t i = 0; i < r.photos.size(); ++i) {
      const PatchMeasurement& m = r.photos[i].measurement.patches[p.index];
      if (!m.usable()) continue;
      SetColour(cr, ToRgb(p.rgb), 0.8);
      Marker(cr, static_cast<int>(i), plane.X(m.lab.a), plane.Y(m.lab.b), 1.8);
      cairo_fill(cr);
    }
  }
}

// The palette: target (large disc) -> each photo's mean (marker).
void DrawPaletteShades(cairo_t* cr, const CalibrationResult& r, const Plane& plane) {
  for (int s = 0; s < 4; ++s) {
    const Shade shade = static_cast<Shade>(s);
    const Lab& target = r.layout.palette[shade];
    const Rgb colour = ToRgb(r.layout.palette.Srgb8(shade));
    for (size_t i = 0; i < r.photos.size(); ++i) {
      const Lab& m = r.photos[i].shades[s].lab;
      cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
      cairo_set_line_width(cr, 0.8);
      cairo_move_to(cr, plane.X(target.a), plane.Y(target.b));
      cairo_line_to(cr, plane.X(m.a), plane.Y(m.b));
      cairo_stroke(cr);
      Marker(cr, static_cast<int>(i), plane.X(m.a), plane.Y(m.b), 4.5);
      SetColour(cr, colour);
      cairo_fill_preserve(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_set_line_width(cr, 0.8);
      cairo_stroke(cr);
    }
    cairo_new_sub_path(cr);
    cairo_arc(cr, plane.X(target.a), plane.Y(target.b), 7, 0, 2 * kPi);
    SetColour(cr, colour);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
    Text(cr, plane.X(target.a) + 9, plane.Y(target.b) - 6, 8, ShadeName(shade), true);
  }
}

// The chosen palette, as printed (mean over photos): rings.
void DrawChosenPalette(cairo_t* cr, const CalibrationResult& r, const Plane& plane) {
  if (!r.palette) return;
  for (int s = 0; s < 4; ++s) {
    Lab mean;
    const auto& measured = r.palette->shades[s].measured;
    for (const Lab& m : measured) {
      mean.a += m.a / measured.size();
      mean.b += m.b / measured.size();
    }
    cairo_new_sub_path(cr);
    cairo_arc(cr, plane.X(mean.a), plane.Y(mean.b), 6, 0, 2 * kPi);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 2.0);
    cairo_stroke(cr);
  }
}

// Below the plane: what its marks mean, and each photo's marker with the photo's name.
void DrawPlaneLegend(cairo_t* cr, const CalibrationResult& r) {
  // Legend.
  double y = kPlotY + kPlotSide + 30;
  Text(cr, kPlotX, y, 8,
       "Large discs: palette targets. Markers: each photo's measurement (white-normalised), "
       "joined to its target.");
  Text(cr, kPlotX, y + 11, 8,
       "Grey dots: candidate targets; small markers: candidates as printed. Black rings: the "
       "chosen palette as printed.");
  double x = kPlotX;
  for (size_t i = 0; i < r.photos.size() && i < 8; ++i) {
    Marker(cr, static_cast<int>(i), x + 4, y + 24, 4);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_fill(cr);
    std::string name = r.photos[i].name.substr(r.photos[i].name.find_last_of('/') + 1);
    if (name.size() > 18) name = name.substr(0, 17) + "~";
    Text(cr, x + 12, y + 27, 8, name);
    x += 100;
    if (x > kPlotX + 700) break;
  }
}

void DrawPlane(cairo_t* cr, const CalibrationResult& r) {
  const Plane plane = PlaneFor(r);
  DrawAxes(cr, plane);
  DrawCandidates(cr, r, plane);
  DrawPaletteShades(cr, r, plane);
  DrawChosenPalette(cr, r, plane);
  DrawPlaneLegend(cr, r);
}

double Row(cairo_t* cr, double y, const std::string& label, const std::string& value,
           Rgb colour = {0, 0, 0}) {
  Text(cr, 470, y, 8.5, label);
  Text(cr, 640, y, 8.5, value, false, colour);
  return y + 12;
}

// The thresholds derived and the white balance, from `y` down; returns the
// y below them.
double DrawThresholds(cairo_t* cr, const CalibrationResult& r, double y) {
  const DetectorOptions& d = r.thresholds.options;
  Text(cr, 470, y, 10,
       F("Detector thresholds (safety factor %.1f)", r.options.thresholds.safety_factor), true);
  y += 15;
  const DetectorOptions defaults;
  y = Row(cr, y, "ADiffThresh", F("%.1f   (default %.0f)", d.adiff_thresh, defaults.adiff_thresh));
  y = Row(cr, y, "BorderThresh",
          F("%.1f   (default %.0f)", d.border_thresh, defaults.border_thresh));
  y = Row(cr, y, "min decision margin",
          F("%.1f   (default %.0f)", d.min_decision_margin, defaults.min_decision_margin));
  y = Row(cr, y, "max green a*", F("%.1f   (default %.0f)", d.max_green_a, defaults.max_green_a));
  y = Row(cr, y, "two-step rises",
          std::string(d.two_step_rises ? "on" : "off") + "   (default " +
              (defaults.two_step_rises ? "on" : "off") + ")");
  const WhiteBalanceGains& g = r.white_balance.gains;
  const WhiteBalanceOutcome outcome = r.white_balance.outcome;
  y = Row(cr, y, "white balance, R / G / B",
          outcome == WhiteBalanceOutcome::kWritten     ? F("%.3f / %.3f / %.3f", g[0], g[1], g[2])
          : outcome == WhiteBalanceOutcome::kNotNeeded ? std::string("none: not needed")
                                                       : std::string("none: see the warnings"));
  return y;
}

// The palette chosen, its shades and gaps, from `y` down.
void DrawPaletteChoice(cairo_t* cr, const CalibrationResult& r, double y) {
  Text(cr, 470, y, 10, "Chosen palette (as printed, worst case)", true);
  y += 15;
  if (!r.palette) {
    Text(cr, 470, y, 8.5, "none: see the warnings");
    return;
  }
  const PaletteChoice& p = *r.palette;
  for (int s = 0; s < 4; ++s) {
    const Lab& lab = p.shades[s].intended;
    Swatch(cr, 470, y - 8, 10, ToRgb(LabToSrgb8(lab)));
    Text(cr, 485, y, 8.5,
         std::string(ShadeName(static_cast<Shade>(s))) +
             F("  file L*a*b* %.1f %.1f %.1f", lab.L, lab.a, lab.b) +
             (p.shades[s].patch < 0 ? "  (sheet palette)" : ""));
    y += 12;
  }
  y = Row(cr, y, "a* gap / b* gaps", F("%.1f / %.1f / %.1f", p.a_gap, p.red_b_gap, p.green_b_gap));
  Row(cr, y, "score (1 = spec design goals)",
      F("%.2f   (sheet palette %.2f)", p.score, p.sheet_palette_score));
}

void DrawNumbers(cairo_t* cr, const CalibrationResult& r) {
  const Margins& w = r.thresholds.worst;
  double y = kPlotY + 4;
  Text(cr, 470, y, 10, "Worst case over photos (sheet palette)", true);
  y += 15;
  y = Row(cr, y, "a* gap, reds - greens", F("%.1f", w.a_gap));
  y = Row(cr, y, "b* gap, red-1 - red-0", F("%.1f", w.red_b_gap));
  y = Row(cr, y, "b* gap, green-0 - green-1", F("%.1f", w.green_b_gap));
  y = Row(cr, y, "a* spread within a colour", F("%.1f", w.a_spread));
  y = Row(cr, y, "a* of the redder green", F("%.1f", w.max_green_a));
  y = Row(cr, y, "pixel noise (a*)", F("%.1f", w.noise_a));
  y = Row(cr, y, "expected decision margin", F("%.1f", w.decision()));
  y += 8;
  y = DrawThresholds(cr, r, y);
  y += 8;
  Text(cr, 470, y, 10, "Verdict per pair", true);
  y += 15;
  for (const PairVerdict& v : r.thresholds.verdicts) {
    y = Row(cr, y, v.pair, std::string(VerdictName(v.verdict)) + F("  (%.1f)", v.worst_gap),
            VerdictColour(v.verdict));
  }
  y += 8;
  DrawPaletteChoice(cr, r, y);
}

Rgb DeltaEColour(double de) {
  if (de < 1) return {0.55, 0.85, 0.55};
  if (de < 2) return {0.85, 0.9, 0.45};
  if (de < 4) return {0.98, 0.75, 0.4};
  return {0.95, 0.45, 0.4};
}

void DrawMap(cairo_t* cr, const CalibrationResult& r, size_t index, double x0, double y0) {
  const PhotoResult& photo = r.photos[index];
  std::string name = photo.name.substr(photo.name.find_last_of('/') + 1);
  if (name.size() > 30) name = name.substr(0, 29) + "~";
  Text(cr, x0, y0, 9, name, true);
  // Two short lines: one long line ran into the next map's ("0 flaggedmodel").
  Text(cr, x0, y0 + 11, 7.5,
       F("model CIEDE2000 mean %.2f, max %.2f", photo.fit.mean_de, photo.fit.max_de));
  const int flagged = photo.measurement.flagged;
  Text(cr, x0, y0 + 20, 7.5,
       std::to_string(flagged) + (flagged == 1 ? " patch" : " patches") + " flagged");
  const double cell = std::min((kMapWidth - 10) / r.layout.columns, 250.0 / r.layout.rows);
  const double top = y0 + 27;
  std::vector<double> residual(r.layout.patches.size(), -1);
  for (size_t i = 0; i < photo.fit_patches.size(); ++i)
    residual[photo.fit_patches[i]] = photo.fit.residual_de[i];
  for (const Patch& p : r.layout.patches) {
    const double x = x0 + p.col * cell, y = top + p.row * cell;
    const PatchMeasurement& m = photo.measurement.patches[p.index];
    cairo_rectangle(cr, x + 0.5, y + 0.5, cell - 1, cell - 1);
    if (!m.usable()) {
      cairo_set_source_rgb(cr, 0.75, 0.75, 0.75);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
      cairo_set_line_width(cr, 0.6);
      cairo_move_to(cr, x + 2, y + 2);
      cairo_line_to(cr, x + cell - 2, y + cell - 2);
      cairo_move_to(cr, x + cell - 2, y + 2);
      cairo_line_to(cr, x + 2, y + cell - 2);
      cairo_stroke(cr);
      continue;
    }
    SetColour(cr, DeltaEColour(residual[p.index]));
    cairo_fill(cr);
    // The patch's own colour as a small swatch in the corner.
    cairo_rectangle(cr, x + 1, y + 1, cell * 0.28, cell * 0.28);
    SetColour(cr, p.kind == PatchKind::kPaper ? Rgb{1, 1, 1} : ToRgb(p.rgb));
    cairo_fill(cr);
    Text(cr, x + cell * 0.18, y + cell * 0.8, cell * 0.36, F("%.1f", residual[p.index]));
  }
}

void DrawLegendAndWarnings(cairo_t* cr, const CalibrationResult& r, double y) {
  const double swatches[4] = {0.5, 1.5, 3, 5};
  const char* labels[4] = {"< 1", "1-2", "2-4", ">= 4"};
  Text(cr, 40, y, 8,
       "CIEDE2000 between the model and the measurement, per patch, in sheet layout:");
  // The key on a line of its own, below the sentence it explains.
  y += 14;
  for (int i = 0; i < 4; ++i) {
    Swatch(cr, 40 + i * 60, y - 8, 10, DeltaEColour(swatches[i]));
    Text(cr, 54 + i * 60, y, 8, labels[i]);
  }
  Text(cr, 290, y, 8, "crossed: flagged, not used");
  y += 20;
  Text(cr, 40, y, 10, r.warnings.empty() ? "No warnings." : "Warnings", true);
  for (const std::string& w : r.warnings) {
    y += 12;
    Text(cr, 40, y, 7.5, w.size() > 190 ? w.substr(0, 189) + "~" : w, false, {0.6, 0.1, 0.1});
  }
}

int MapRows(const CalibrationResult& r) {
  return static_cast<int>((r.photos.size() + kMapsPerRow - 1) / kMapsPerRow);
}

}  // namespace

double ReportHeight(const CalibrationResult& result) {
  return kMapTop + MapRows(result) * kMapRowHeight + 64 + 12.0 * result.warnings.size();
}

void DrawReport(cairo_t* cr, const CalibrationResult& r) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  Verdict overall = Verdict::kGood;
  for (const PairVerdict& v : r.thresholds.verdicts) overall = std::max(overall, v.verdict);
  Text(cr, 40, 36, 15, "ChromaTag calibration report", true);
  Text(cr, 40, 54, 9,
       "sheet " + std::to_string(r.layout.sheet_id) + ", palette " + r.layout.palette.name + ", " +
           std::to_string(r.photos.size()) + " photo(s); chromatag " + kVersion);
  Text(cr, 40, 72, 11, std::string("Verdict: ") + VerdictName(overall), true,
       VerdictColour(overall));
  DrawPlane(cr, r);
  DrawNumbers(cr, r);
  for (size_t i = 0; i < r.photos.size(); ++i) {
    const double x = 40 + (i % kMapsPerRow) * kMapWidth;
    const double y = kMapTop + (i / kMapsPerRow) * kMapRowHeight;
    DrawMap(cr, r, i, x, y);
  }
  DrawLegendAndWarnings(cr, r, kMapTop + MapRows(r) * kMapRowHeight + 10);
}

PageSize ReportPage(const CalibrationResult& result) {
  const std::string& name = result.layout.page.name;
  if (name == "a4" || name == "letter" || name == "a3" || name == "legal")
    return result.layout.page;
  return {"a4", 210.0, 297.0};
}

std::string RenderReportPdf(const CalibrationResult& result) {
  // On the calibration sheet's paper (A4 unless it was Letter, A3 or
  // Legal), the report scaled to fit within 10 mm margins.
  const PageSize page = ReportPage(result);
  constexpr double kPointsPerMm = 72.0 / 25.4;
  const double width = page.width_mm * kPointsPerMm, height = page.height_mm * kPointsPerMm;
  const double margin = 10.0 * kPointsPerMm;
  const double scale =
      std::min((width - 2 * margin) / kReportWidth, (height - 2 * margin) / ReportHeight(result));
  return RenderPdf(width, height, "ChromaTag calibration report", 1, [&](cairo_t* cr, int) {
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_translate(cr, (width - kReportWidth * scale) / 2, margin);
    cairo_scale(cr, scale, scale);
    DrawReport(cr, result);
  });
}

std::vector<std::string> ReportOverlaps(const CalibrationResult& result) {
  cairo_surface_t* surface = cairo_recording_surface_create(CAIRO_CONTENT_COLOR, nullptr);
  cairo_t* cr = cairo_create(surface);
  std::vector<Box> boxes;
  g_boxes = &boxes;
  DrawReport(cr, result);
  g_boxes = nullptr;
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
  std::vector<std::string> overlaps;
  constexpr double kSlack = 0.3;  // Glyph boxes of neighbouring lines may touch.
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& a = boxes[i];
    if (a.x1 > kReportWidth + kSlack)
      overlaps.push_back(a.what + " runs past the report's right edge");
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      const Box& b = boxes[j];
      if (a.x0 < b.x1 - kSlack && b.x0 < a.x1 - kSlack && a.y0 < b.y1 - kSlack &&
          b.y0 < a.y1 - kSlack)
        overlaps.push_back(a.what + " overlaps " + b.what);
    }
  }
  return overlaps;
}

std::string RenderReportPng(const CalibrationResult& result, double scale) {
  const int width = static_cast<int>(std::lround(kReportWidth * scale));
  const int height = static_cast<int>(std::lround(ReportHeight(result) * scale));
  return RenderPng(width, height, 0, [&](cairo_t* cr) {
    cairo_scale(cr, scale, scale);
    DrawReport(cr, result);
  });
}

}  // namespace chromatag
