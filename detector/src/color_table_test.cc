#include "chromatag/detector/color_table.h"

#include <gtest/gtest.h>

#include <cmath>

#include "chromatag/families/color.h"

namespace chromatag {
namespace {

// Every one of the 16.7 million 8-bit colours against the exact formula
// (families/color.h): the accurate path is within 0.05 in L*, a*, b*; the
// coarse a* within the bound FindADiff relies on.
TEST(ColorTableTest, MatchesTheExactFormulaForEveryColour) {
  const ColorTable& table = ColorTable::Get();
  double linear[256];
  for (int v = 0; v < 256; ++v) linear[v] = SrgbToLinear(v / 255.0);
  double worst_l = 0, worst_a = 0, worst_b = 0, worst_coarse = 0;
  for (int r = 0; r < 256; ++r) {
    for (int g = 0; g < 256; ++g) {
      for (int b = 0; b < 256; ++b) {
        const Lab exact = XyzToLab(LinearRgbToXyz({linear[r], linear[g], linear[b]}));
        const LabF fast = table.Lab(r, g, b);
        worst_l = std::max(worst_l, std::abs(fast.L - exact.L));
        worst_a = std::max(worst_a, std::abs(fast.a - exact.a));
        worst_b = std::max(worst_b, std::abs(fast.b - exact.b));
        worst_coarse = std::max(worst_coarse, std::abs(table.CoarseA(r, g, b) - exact.a));
      }
    }
  }
  EXPECT_LT(worst_l, 0.05);
  EXPECT_LT(worst_a, 0.05);
  EXPECT_LT(worst_b, 0.05);
  EXPECT_LE(worst_coarse, ColorTable::kCoarseErrorBound);
  // The bound is not loose either: FindADiff's prefilter passes rises down to
  // ADiffThresh minus twice the bound.
  EXPECT_GT(worst_coarse, ColorTable::kCoarseErrorBound - 2);
  std::printf("worst |error|: L* %.4f a* %.4f b* %.4f, coarse a* %.2f\n", worst_l, worst_a, worst_b,
              worst_coarse);
}

TEST(ColorTableTest, SingleChannelsAgreeWithLab) {
  const ColorTable& table = ColorTable::Get();
  for (int v = 0; v < 256; v += 5) {
    const LabF lab = table.Lab(v, 255 - v, v / 2);
    EXPECT_FLOAT_EQ(table.A(v, 255 - v, v / 2), lab.a);
    EXPECT_FLOAT_EQ(table.L(v, 255 - v, v / 2), lab.L);
  }
}

TEST(ColorTableTest, IsKilobytesNotMegabytes) {
  EXPECT_LT(ColorTable::Get().memory_bytes(), 64u * 1024u);
}

}  // namespace
}  // namespace chromatag
