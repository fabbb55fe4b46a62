// SheetOptions::IsValid and LayoutSheet: where every tag goes on the page.
#include <cmath>
#include <cstdio>
#include <utility>

#include "chromatag/generator/cairo_util.h"
#include "chromatag/generator/sheet.h"
#include "sheet_internal.h"

namespace chromatag {
namespace internal {

std::string Mm(double mm) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.1f", mm);
  return buffer;
}

double LabelHeightMm(const SheetOptions& options) {
  return options.label ? LabelFontMm(options) * kLabelLineFactor : 0.0;
}

double LabelFontMm(const SheetOptions& options) {
  const double cell = options.tag_size_mm / options.family->black_square_cells();
  return std::fmin(std::fmax(cell * 0.5, 1.8), 3.5);
}

double MarksMm(const SheetOptions& options) { return options.crop_marks ? kCropMarkReachMm : 0.0; }

double OuterMm(const SheetOptions& options) {
  return options.tag_size_mm * OuterCells(*options.family, options.tag) /
         options.family->black_square_cells();
}

UsableMm Usable(const SheetOptions& options, bool turned) {
  const double w = turned ? options.page.height_mm : options.page.width_mm;
  const double h = turned ? options.page.width_mm : options.page.height_mm;
  return {w - 2.0 * options.margin_mm, h - 2.0 * options.margin_mm - kScaleStripMm};
}

double QuietZoneMm(const SheetOptions& options) {
  return options.tag_size_mm * options.tag.quiet_zone_cells / options.family->black_square_cells();
}

}  // namespace internal

bool SheetOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!family) return fail("no tag family given (16h5, 36h11)");
  if (ids.empty()) return fail("no tag IDs given");
  for (int id : ids) {
    std::string why;
    if (!family->IsValidId(id, &why)) return fail(why);
  }
  if (!(tag_size_mm >= 1.0 && tag_size_mm <= kMaxPageSideMm)) {
    return fail("the tag size must be from 1 mm to 10 m");
  }
  if (!(page.width_mm > 0.0 && page.height_mm > 0.0 && page.width_mm <= kMaxPageSideMm &&
        page.height_mm <= kMaxPageSideMm)) {
    return fail("the page sides must be greater than zero and at most 10 m");
  }
  if (!(margin_mm >= 0.0) || 2.0 * margin_mm >= std::fmin(page.width_mm, page.height_mm)) {
    return fail("the margin must be >= 0 and leave room on the page");
  }
  if (!(gap_mm >= 0.0 && gap_mm <= kMaxPageSideMm))
    return fail("the gap between tags must be from 0 to 10 m");
  if (tag.quiet_zone_cells < 1 || tag.quiet_zone_cells > 20) {
    return fail("the quiet zone must be 1 to 20 cells (the detector needs at least 1)");
  }
  if (board) {
    if (board->columns < 1 || board->rows < 1 || board->columns > 100 || board->rows > 100)
      return fail("a board is 1 to 100 tags wide and high (COLSxROWS, e.g. 6x4)");
    const size_t n = static_cast<size_t>(board->columns) * static_cast<size_t>(board->rows);
    if (ids.size() != n) {
      return fail("a " + std::to_string(board->columns) + "x" + std::to_string(board->rows) +
                  " board holds " + std::to_string(n) + " tags, but " + std::to_string(ids.size()) +
                  " IDs were given");
    }
    if (one_per_page || tag.cut_ring || crop_marks)
      return fail("a board is one page of tags: no tag per page, cut ring or crop marks");
    const double quiet = tag_size_mm * tag.quiet_zone_cells / family->black_square_cells();
    if (!(board->spacing_mm >= quiet - 1e-9 && board->spacing_mm <= kMaxPageSideMm)) {
      return fail("the spacing between a board's tags must be at least their quiet zone, " +
                  internal::Mm(quiet) + " mm for " + internal::Mm(tag_size_mm) + " mm " +
                  family->name() + " tags with " + std::to_string(tag.quiet_zone_cells) + " cells");
    }
  }
  if (format == SheetFormat::kPng) {
    if (!(dpi >= 10.0 && dpi <= 4800.0)) return fail("the resolution must be in [10, 4800] dpi");
    const std::string problem = RasterPageProblem(page.width_mm, page.height_mm, dpi);
    if (!problem.empty()) return fail("a PNG sheet: " + problem + "; lower the resolution");
  }
  return true;
}

namespace {

// LayoutSheet for a board: one grid, centred in the usable area with the
// axes band on its left and below.
std::optional<SheetLayout> LayoutBoard(const SheetOptions& options, double usable_w,
                                       double usable_h, SheetLayout layout, std::string* error) {
  using internal::kBoardAxesMm;
  using internal::Mm;
  const BoardGrid& board = *options.board;
  const double s = options.tag_size_mm, g = board.spacing_mm;
  const double quiet = internal::QuietZoneMm(options);
  const double grid_w = board.columns * s + (board.columns - 1) * g;
  const double grid_h = board.rows * s + (board.rows - 1) * g;
  const double need_w = grid_w + 2.0 * quiet + kBoardAxesMm;
  const double need_h = grid_h + 2.0 * quiet + kBoardAxesMm;
  if (need_w > usable_w + 1e-9 || need_h > usable_h + 1e-9) {
    if (error) {
      *error =
          "a " + std::to_string(board.columns) + "x" + std::to_string(board.rows) + " board of " +
          Mm(s) + " mm tags " + Mm(g) + " mm apart needs " + Mm(need_w) + " x " + Mm(need_h) +
          " mm with its quiet zone and axes; page " + options.page.name + " with " +
          Mm(options.margin_mm) + " mm margins and the scale bar leaves " + Mm(usable_w) + " x " +
          Mm(usable_h) + " mm" +
          (options.page.may_turn ? ", turned " + Mm(internal::Usable(options, true).width) + " x " +
                                       Mm(internal::Usable(options, true).height) + " mm"
                                 : std::string()) +
          " (give no tag size for the largest that fits)";
    }
    return std::nullopt;
  }
  layout.num_pages = 1;
  layout.columns = board.columns;
  layout.rows = board.rows;
  layout.footprint_width_mm = layout.footprint_height_mm = internal::OuterMm(options);
  const double x0 = options.margin_mm + (usable_w - need_w) / 2.0 + kBoardAxesMm + quiet;
  const double y0 = options.margin_mm + (usable_h - need_h) / 2.0 + quiet;
  const double px_per_mm = options.dpi / 25.4;
  const double cell_px = s / options.family->black_square_cells() * px_per_mm;
  const bool snap =
      options.format == SheetFormat::kPng && std::fabs(cell_px - std::round(cell_px)) < 1e-6;
  const auto place = [&](double v) { return snap ? std::round(v * px_per_mm) / px_per_mm : v; };
  for (size_t i = 0; i < options.ids.size(); ++i) {
    const int column = static_cast<int>(i) % board.columns,
              row = static_cast<int>(i) / board.columns;
    const double x = place(x0 + column * (s + g)), y = place(y0 + row * (s + g));
    PlacedTag placed;
    placed.id = options.ids[i];
    placed.page = 0;
    placed.corners_mm = {{{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}}};
    placed.center_mm = {x + s / 2.0, y + s / 2.0};
    layout.tags.push_back(placed);
  }
  // The bottom-left tag's black square, bottom-left corner.
  const PlacedTag& corner = layout.tags[static_cast<size_t>(board.rows - 1) * board.columns];
  layout.board_origin_mm = corner.corners_mm[3];
  return layout;
}

// LayoutSheet for a sheet: as many tags (with their marks and label) as fit
// across and down, page after page, the grid centred in the usable area.
SheetLayout LayoutTagGrid(const SheetOptions& options, double usable_w, double usable_h,
                          SheetLayout layout) {
  const double marks = internal::MarksMm(options);
  const double outer = internal::OuterMm(options);
  const double gap = options.gap_mm;
  layout.columns = options.one_per_page
                       ? 1
                       : static_cast<int>((usable_w + gap) / (layout.footprint_width_mm + gap));
  layout.rows = options.one_per_page
                    ? 1
                    : static_cast<int>((usable_h + gap) / (layout.footprint_height_mm + gap));
  const int per_page = layout.columns * layout.rows;
  const int n = static_cast<int>(options.ids.size());
  layout.num_pages = (n + per_page - 1) / per_page;

  // The grid is centred in the usable area.
  const double grid_w = layout.columns * layout.footprint_width_mm + (layout.columns - 1) * gap;
  const double grid_h = layout.rows * layout.footprint_height_mm + (layout.rows - 1) * gap;
  const double x0 = options.margin_mm + (usable_w - grid_w) / 2.0;
  const double y0 = options.margin_mm + (usable_h - grid_h) / 2.0;
  // PNG: with a whole number of pixels per cell, put the black square on a
  // pixel edge so every cell edge is one.
  const double px_per_mm = options.dpi / 25.4;
  const double cell_px = options.tag_size_mm / options.family->black_square_cells() * px_per_mm;
  const bool snap =
      options.format == SheetFormat::kPng && std::fabs(cell_px - std::round(cell_px)) < 1e-6;
  const double inset = marks + (outer - options.tag_size_mm) / 2.0;
  for (int i = 0; i < n; ++i) {
    const int slot = i % per_page;
    double x = x0 + (slot % layout.columns) * (layout.footprint_width_mm + gap) + inset;
    double y = y0 + (slot / layout.columns) * (layout.footprint_height_mm + gap) + inset;
    if (snap) {
      x = std::round(x * px_per_mm) / px_per_mm;
      y = std::round(y * px_per_mm) / px_per_mm;
    }
    const double s = options.tag_size_mm;
    PlacedTag placed;
    placed.id = options.ids[i];
    placed.page = i / per_page;
    placed.corners_mm = {{{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}}};
    placed.center_mm = {x + s / 2.0, y + s / 2.0};
    layout.tags.push_back(placed);
  }
  layout.board_origin_mm = {0.0, options.page.height_mm};
  return layout;
}

}  // namespace

std::optional<SheetLayout> LayoutSheet(const SheetOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  using namespace internal;
  SheetLayout layout;
  const double marks = MarksMm(options);
  const double outer = OuterMm(options);
  layout.footprint_width_mm = outer + 2.0 * marks;
  layout.footprint_height_mm = outer + 2.0 * marks + LabelHeightMm(options);

  const auto [usable_w, usable_h] = Usable(options);
  for (double bar : {100.0, 50.0, 20.0, 10.0}) {
    if (bar <= usable_w) {
      layout.scale_bar_mm = bar;
      break;
    }
  }
  if (layout.scale_bar_mm == 0.0 || usable_h <= 0.0) {
    if (error) *error = "the page leaves no room inside its margins for tags and the scale bar";
    return std::nullopt;
  }
  if (options.board) return LayoutBoard(options, usable_w, usable_h, std::move(layout), error);
  if (layout.footprint_width_mm > usable_w || layout.footprint_height_mm > usable_h) {
    if (error) {
      *error = "a " + Mm(options.tag_size_mm) + " mm " + options.family->name() + " tag needs " +
               Mm(layout.footprint_width_mm) + " x " + Mm(layout.footprint_height_mm) +
               " mm of paper with its quiet zone" + (options.label ? " and label" : "") +
               "; page " + options.page.name + " (" + Mm(options.page.width_mm) + " x " +
               Mm(options.page.height_mm) + " mm) with " + Mm(options.margin_mm) +
               " mm margins and the scale bar leaves " + Mm(usable_w) + " x " + Mm(usable_h) +
               " mm";
    }
    return std::nullopt;
  }
  return LayoutTagGrid(options, usable_w, usable_h, std::move(layout));
}

std::optional<double> BoardTagSizeToFit(const SheetOptions& options, double spacing_share,
                                        std::string* error) {
  using internal::kBoardAxesMm;
  const auto fail = [&](const std::string& message) -> std::optional<double> {
    if (error) *error = message;
    return std::nullopt;
  };
  if (!options.family || !options.board || options.board->columns < 1 || options.board->rows < 1)
    return fail("no board to fit");
  const auto [usable_w, usable_h] = internal::Usable(options);
  const double quiet = 2.0 * options.tag.quiet_zone_cells / options.family->black_square_cells();
  // Extent = n s + (n - 1) spacing + 2 quiet zones + the axes band.
  const auto fit = [&](int n, double room) {
    const double spacing = spacing_share > 0 ? 0.0 : options.board->spacing_mm;
    const double share = spacing_share > 0 ? spacing_share : 0.0;
    return (room - kBoardAxesMm - (n - 1) * spacing) / (n + (n - 1) * share + quiet);
  };
  double size =
      std::fmin(fit(options.board->columns, usable_w), fit(options.board->rows, usable_h));
  size = size >= 10.0 ? std::floor(size) : std::floor(size * 10.0 + 1e-9) / 10.0;
  if (!(size >= 1.0)) {
    return fail("a " + std::to_string(options.board->columns) + "x" +
                std::to_string(options.board->rows) + " board does not fit page " +
                options.page.name + " even with 1 mm tags");
  }
  return size;
}

}  // namespace chromatag
