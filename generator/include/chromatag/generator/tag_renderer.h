// Drawing one ChromaTag with Cairo (spec section 1), as vector paths.
//
// Cells of one shade are one filled path, and the shades are layered (black
// square, then the whole payload in green-0, the red centre in red-0, then the
// green-1 and red-1 cells) so that no two fills merely abut over a darker
// background: there is no seam or hairline at any zoom or resolution.
#ifndef CHROMATAG_GENERATOR_TAG_RENDERER_H_
#define CHROMATAG_GENERATOR_TAG_RENDERER_H_

#include <cairo.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"

namespace chromatag {

// The gamma-encoded sRGB (channels in [0, 1]) written for each shade.
struct TagColors {
  std::array<Rgb, kNumShades> rgb;

  const Rgb& operator[](Shade shade) const { return rgb[static_cast<int>(shade)]; }
  Rgb& operator[](Shade shade) { return rgb[static_cast<int>(shade)]; }

  // The palette's CIELAB values as sRGB, rounded to 8 bits (what a PNG or an
  // 8-bit printer pipeline can hold, and what the tests compare against).
  static TagColors FromPalette(const Palette& palette);
};

struct TagDrawOptions {
  // White quiet zone around the black square, in cells. >= 1 (the detector
  // needs one); the authors print 2.
  int quiet_zone_cells = 2;
  // A 1-cell light grey ring outside the quiet zone to cut along.
  bool cut_ring = false;
  Rgb cut_ring_color{0.85, 0.85, 0.85};
};

// Side of the whole drawn tag in cells: black square + 2 quiet zones (+ 2 for
// the cut ring).
int OuterCells(const TagFamily& family, const TagDrawOptions& options);

// Draws tag `id` with the current transform of `cr`: the black square spans
// [x, x + tag_size] x [y, y + tag_size] in user units, the quiet zone and cut
// ring lie outside it. Requires a kept ID (TagFamily::IsValidId).
void DrawTag(cairo_t* cr, const TagFamily& family, int id, const TagColors& colors, double x,
             double y, double tag_size, const TagDrawOptions& options = {});

// 8-bit RGB pixels, row-major, 3 bytes per pixel, no padding.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;
  const uint8_t* At(int x, int y) const {
    return &pixels[(static_cast<size_t>(y) * width + x) * 3];
  }
};

// Renders one tag with its quiet zone (and cut ring) to pixels, `pixels_per_cell`
// per cell, the black square's top-left corner at pixel edge
// (OuterCells - black_square_cells) / 2 * pixels_per_cell. With a whole number
// of pixels per cell every cell edge falls on a pixel edge.
RgbImage RasterizeTag(const TagFamily& family, int id, const TagColors& colors,
                      double pixels_per_cell, const TagDrawOptions& options = {});

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_TAG_RENDERER_H_
