#include "kernels/color_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "chromatag/families/color.h"

namespace chromatag::internal {
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

// FindADiff's AVX-512 path relies on the computed a* being within its bound
// of the accurate path (the one its re-check uses) for every colour.
TEST(ColorTableTest, ComputedAIsWithinItsBoundForEveryColour) {
  const ColorTable& table = ColorTable::Get();
  double worst = 0;
  for (int r = 0; r < 256; ++r) {
    for (int g = 0; g < 256; ++g) {
      for (int b = 0; b < 256; ++b) {
        const double fast = table.FastA(r, g, b) / ColorTable::kFastAUnitsPerA;
        worst = std::max(worst, std::abs(fast - table.A(r, g, b)));
      }
    }
  }
  EXPECT_LE(worst, ColorTable::kFastAErrorBound);
  // Not loose: the path passes rises down to ADiffThresh minus twice it.
  EXPECT_GT(worst, ColorTable::kFastAErrorBound - 0.25);
  std::printf("worst |computed a* - a*|: %.3f\n", worst);
}

TEST(ColorTableTest, SingleChannelsAgreeWithLab) {
  const ColorTable& table = ColorTable::Get();
  for (int v = 0; v < 256; v += 5) {
    const LabF lab = table.Lab(v, 255 - v, v / 2);
    EXPECT_FLOAT_EQ(table.A(v, 255 - v, v / 2), lab.a);
    EXPECT_FLOAT_EQ(table.L(v, 255 - v, v / 2), lab.L);
  }
}

// A colour seen under another light (each channel's linear light scaled,
// clipped at full scale) as the exact formulas give it, for gains that darken
// and that lift a channel past full scale.
TEST(ColorTableTest, GainedColoursAgreeWithTheExactFormulas) {
  const ColorTable& table = ColorTable::Get();
  const std::array<float, 3> gains[] = {{1.f, 1.f, 1.f}, {1.6f, 1.f, 0.55f}, {0.5f, 0.9f, 2.5f}};
  for (const auto& gain : gains) {
    double worst = 0;
    for (int r = 0; r < 256; r += 15) {
      for (int g = 0; g < 256; g += 15) {
        for (int b = 0; b < 256; b += 15) {
          const LabF got = table.Lab(r, g, b, gain);
          const uint8_t v[3] = {static_cast<uint8_t>(r), static_cast<uint8_t>(g),
                                static_cast<uint8_t>(b)};
          double lin[3];
          for (int c = 0; c < 3; ++c) lin[c] = std::min(1.0, gain[c] * Srgb8ToLinear(v[c]));
          const Lab want = XyzToLab(LinearRgbToXyz({lin[0], lin[1], lin[2]}));
          worst = std::max({worst, std::abs(got.L - want.L), std::abs(got.a - want.a),
                            std::abs(got.b - want.b)});
        }
      }
    }
    EXPECT_LT(worst, 0.05) << gain[0] << " " << gain[1] << " " << gain[2];
  }
}

// GrowRegion tests many colours against one L* level through Y: the two
// tests must agree for every colour and level, including levels that fall
// exactly on a colour's L*, below black's and above white's.
TEST(ColorTableTest, YForLGivesTheSameAnswerAsL) {
  const ColorTable& table = ColorTable::Get();
  std::vector<float> levels = {-20.f,     0.f,   100.f,
                               100.0001f, 150.f, std::numeric_limits<float>::quiet_NaN()};
  for (float level = 0.25f; level < 100.f; level += 0.731f) levels.push_back(level);
  for (int v = 0; v < 256; v += 17) {
    levels.push_back(table.L(v, v, v));  // Exactly a colour's L*.
    levels.push_back(table.L(v, 255 - v, v / 3));
  }
  for (float level : levels) {
    const int32_t y_level = table.YForL(level);
    int disagreements = 0;
    for (int r = 0; r < 256; r += 3) {
      for (int g = 0; g < 256; g += 3) {
        for (int b = 0; b < 256; b += 5) {
          disagreements += (table.L(r, g, b) < level) != (table.Y(r, g, b) < y_level);
        }
      }
    }
    EXPECT_EQ(disagreements, 0) << "level " << level;
  }
  // Every Y lies below the answer for a level above white's, none below
  // the answer for black's.
  EXPECT_GT(table.YForL(150.f), table.Y(255, 255, 255));
  EXPECT_EQ(table.YForL(-20.f), 0);
  EXPECT_LE(table.YForL(table.L(0, 0, 0)), table.Y(0, 0, 0));
}

TEST(ColorTableTest, IsKilobytesNotMegabytes) {
  EXPECT_LT(ColorTable::Get().memory_bytes(), 64u * 1024u);
}

}  // namespace
}  // namespace chromatag::internal
