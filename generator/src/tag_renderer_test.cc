#include "chromatag/generator/tag_renderer.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

TEST(TagRendererTest, RasterizedCellsCarryTheCodeInThePalettesShades) {
  auto family = TagFamily::Load("16h5");
  const Palette palette = *BuiltinPalette("default");
  const TagColors colors = TagColors::FromPalette(palette);
  const int ppc = 10;
  for (int id : family->kept_ids()) {
    const RgbImage image = RasterizeTag(*family, id, colors, ppc);
    ASSERT_EQ(image.width, 10 * ppc);  // 6-cell black square + 2 x 2 quiet cells.
    const int origin = 2 * ppc;        // Black square's top-left pixel edge.
    auto expect_pixel = [&](int px, int py, Shade shade) {
      const uint8_t* p = image.At(px, py);
      const Rgb8 expected = palette.Srgb8(shade);
      ASSERT_EQ(Rgb8({p[0], p[1], p[2]}), expected)
          << "ID " << id << " pixel (" << px << ", " << py << ") should be " << ShadeName(shade);
    };
    expect_pixel(0, 0, Shade::kWhite);
    expect_pixel(origin + 1, origin + 1, Shade::kBlack);
    expect_pixel(origin - 1, origin + 5, Shade::kWhite);
    for (int row = 0; row < 4; ++row) {
      for (int col = 0; col < 4; ++col) {
        const bool bit = family->Bit(family->CodeOf(id), row, col);
        const bool red = family->CellColorAt(row, col) == CellColor::kRed;
        const Shade shade =
            red ? (bit ? Shade::kRed1 : Shade::kRed0) : (bit ? Shade::kGreen1 : Shade::kGreen0);
        // Every pixel of the cell, edges included: no seam, no blending.
        for (int y = 0; y < ppc; ++y) {
          for (int x = 0; x < ppc; ++x) {
            expect_pixel(origin + (col + 1) * ppc + x, origin + (row + 1) * ppc + y, shade);
          }
        }
      }
    }
  }
}

TEST(TagRendererTest, CutRingAndQuietZoneWidths) {
  auto family = TagFamily::Load("36h11");
  const TagColors colors = TagColors::FromPalette(*BuiltinPalette("default"));
  TagDrawOptions options;
  options.quiet_zone_cells = 1;
  options.cut_ring = true;
  EXPECT_EQ(OuterCells(*family, options), 12);
  const RgbImage image = RasterizeTag(*family, 7, colors, 4, options);
  ASSERT_EQ(image.width, 48);
  EXPECT_EQ(image.At(1, 1)[0], 217);  // Cut ring grey, 0.85 * 255.
  EXPECT_EQ(image.At(5, 5)[0], 255);  // Quiet zone.
  EXPECT_EQ(image.At(9, 9)[0], 0);    // Black ring.
}

}  // namespace
}  // namespace chromatag
