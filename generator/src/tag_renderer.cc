#include "chromatag/generator/tag_renderer.h"

#include <cassert>
#include <cmath>

namespace chromatag {
namespace {

void SetColor(cairo_t* cr, const Rgb& rgb) { cairo_set_source_rgb(cr, rgb.r, rgb.g, rgb.b); }

void FillRect(cairo_t* cr, const Rgb& rgb, double x, double y, double w, double h) {
  SetColor(cr, rgb);
  cairo_rectangle(cr, x, y, w, h);
  cairo_fill(cr);
}

// Adds to the current path every payload cell of `color` whose bit is `bit`;
// returns whether any was added. Cell (row, col) spans [col + 1, col + 2) x
// [row + 1, row + 2) in cells from the black square's corner.
bool AddCells(cairo_t* cr, const TagFamily& family, Code code, CellColor color, bool bit) {
  bool any = false;
  const int d = family.payload_width();
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      if (family.CellColorAt(row, col) != color || family.Bit(code, row, col) != bit) continue;
      cairo_rectangle(cr, col + 1.0, row + 1.0, 1.0, 1.0);
      any = true;
    }
  }
  return any;
}

}  // namespace

TagColors TagColors::FromPalette(const Palette& palette) {
  TagColors colors;
  for (Shade shade : kAllShades) colors[shade] = ToRgb(palette.Srgb8(shade));
  return colors;
}

int OuterCells(const TagFamily& family, const TagDrawOptions& options) {
  return family.black_square_cells() + 2 * options.quiet_zone_cells + (options.cut_ring ? 2 : 0);
}

void DrawTag(cairo_t* cr, const TagFamily& family, int id, const TagColors& colors, double x,
             double y, double tag_size, const TagDrawOptions& options) {
  assert(family.IsValidId(id));
  assert(options.quiet_zone_cells >= 1);
  const int d = family.payload_width();
  const double cells = family.black_square_cells();
  const Code code = family.CodeOf(id);

  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_scale(cr, tag_size / cells, tag_size / cells);  // User units are cells now.
  cairo_set_fill_rule(cr, CAIRO_FILL_RULE_WINDING);

  const double q = options.quiet_zone_cells;
  if (options.cut_ring) {
    FillRect(cr, options.cut_ring_color, -q - 1.0, -q - 1.0, cells + 2.0 * q + 2.0,
             cells + 2.0 * q + 2.0);
  }
  FillRect(cr, colors[Shade::kWhite], -q, -q, cells + 2.0 * q, cells + 2.0 * q);
  FillRect(cr, colors[Shade::kBlack], 0.0, 0.0, cells, cells);
  // Layers: each lies fully on the one below, so anti-aliased edges blend two
  // tag colours and never let black through.
  FillRect(cr, colors[Shade::kGreen0], 1.0, 1.0, d, d);
  FillRect(cr, colors[Shade::kRed0], 2.0, 2.0, d - 2.0, d - 2.0);
  if (AddCells(cr, family, code, CellColor::kGreen, true)) {
    SetColor(cr, colors[Shade::kGreen1]);
    cairo_fill(cr);
  }
  if (AddCells(cr, family, code, CellColor::kRed, true)) {
    SetColor(cr, colors[Shade::kRed1]);
    cairo_fill(cr);
  }
  cairo_restore(cr);
}

RgbImage RasterizeTag(const TagFamily& family, int id, const TagColors& colors,
                      double pixels_per_cell, const TagDrawOptions& options) {
  const int outer = OuterCells(family, options);
  const int side = static_cast<int>(std::ceil(outer * pixels_per_cell - 1e-9));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, side, side);
  cairo_t* cr = cairo_create(surface);
  FillRect(cr, colors[Shade::kWhite], 0, 0, side, side);
  const double margin = (outer - family.black_square_cells()) / 2.0 * pixels_per_cell;
  DrawTag(cr, family, id, colors, margin, margin, family.black_square_cells() * pixels_per_cell,
          options);
  cairo_destroy(cr);
  cairo_surface_flush(surface);

  RgbImage image;
  image.width = side;
  image.height = side;
  image.pixels.resize(static_cast<size_t>(side) * side * 3);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  for (int y = 0; y < side; ++y) {
    const uint32_t* row = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < side; ++x) {
      uint8_t* out = &image.pixels[(static_cast<size_t>(y) * side + x) * 3];
      out[0] = static_cast<uint8_t>(row[x] >> 16);  // RGB24 is 0x00RRGGBB per pixel.
      out[1] = static_cast<uint8_t>(row[x] >> 8);
      out[2] = static_cast<uint8_t>(row[x]);
    }
  }
  cairo_surface_destroy(surface);
  return image;
}

}  // namespace chromatag
