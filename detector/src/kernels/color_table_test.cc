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

// The gain sets the white balance tests use: casts a camera's white
// balance corrects (a tungsten lamp, 0.6 / 1 / 0.6 and its opposite) and
// the extremes DetectorOptions allows (kMinWhiteBalanceGain, 0.2).
const ColorTable::Gains kGainSets[] = {{1.0, 0.6, 1.0}, {0.6, 1.0, 0.6}, {0.45, 0.7, 1.0},
                                       {1.0, 0.2, 0.2}, {0.2, 1.0, 0.2}, {0.2, 0.2, 1.0},
                                       {1.0, 1.0, 0.2}, {0.2, 1.0, 1.0}, {1.0, 0.2, 1.0}};

struct Worst {
  double l = 0, a = 0, b = 0, coarse = 0, fast = 0;
};

// Worst errors of `table` over the colours whose channels are multiples of
// `stride` (and 255): the accurate path against the exact conversion of the
// gained colour, the coarse a* against the exact a*, the computed a*
// against the accurate one.
Worst WorstErrors(const ColorTable& table, int stride) {
  const ColorTable::Gains& gains = table.gains();
  std::vector<int> values;
  for (int v = 0; v < 255; v += stride) values.push_back(v);
  values.push_back(255);
  double linear[256];
  for (int v = 0; v < 256; ++v) linear[v] = SrgbToLinear(v / 255.0);
  Worst w;
  for (int r : values) {
    for (int g : values) {
      for (int b : values) {
        const Lab exact = XyzToLab(
            LinearRgbToXyz({gains[0] * linear[r], gains[1] * linear[g], gains[2] * linear[b]}));
        const LabF fast = table.Lab(r, g, b);
        w.l = std::max(w.l, std::abs(fast.L - exact.L));
        w.a = std::max(w.a, std::abs(fast.a - exact.a));
        w.b = std::max(w.b, std::abs(fast.b - exact.b));
        w.coarse = std::max(w.coarse, std::abs(table.CoarseA(r, g, b) - exact.a));
        const double computed = table.FastA(r, g, b) / ColorTable::kFastAUnitsPerA;
        w.fast = std::max(w.fast, std::abs(computed - table.A(r, g, b)));
      }
    }
  }
  return w;
}

// Every colour for the first gain set (a green cast's, whose computed a*
// comes closest to its bound: 2.50), every third level of each channel for
// the others (every colour for all of them: coarse a* within 5.18, computed
// a* within 2.50, 11 s).
TEST(ColorTableTest, GainsAreFoldedIntoEveryPath) {
  bool first = true;
  for (const ColorTable::Gains& gains : kGainSets) {
    const ColorTable table(gains);
    const Worst w = WorstErrors(table, first ? 1 : 3);
    first = false;
    std::printf(
        "gains %.2f %.2f %.2f: worst |error| L* %.4f a* %.4f b* %.4f, coarse %.2f, "
        "computed %.3f\n",
        gains[0], gains[1], gains[2], w.l, w.a, w.b, w.coarse, w.fast);
    EXPECT_LT(w.l, 0.05);
    EXPECT_LT(w.a, 0.05);
    EXPECT_LT(w.b, 0.05);
    EXPECT_LE(w.coarse, ColorTable::kCoarseErrorBound);
    EXPECT_LE(w.fast, ColorTable::kFastAErrorBound);
  }
}

// The paper white under a cast, balanced: a green-tinted white (as a
// camera's green channel reads a tungsten-lit page against a daylight
// setting's red and blue) reads neutral through the gains that undo it.
TEST(ColorTableTest, GainsNeutraliseTheCastTheyUndo) {
  const ColorTable plain;
  const ColorTable balanced({1.0, 0.6, 1.0});
  const int g = static_cast<int>(std::lround(255 * LinearToSrgb(SrgbToLinear(150 / 255.0) / 0.6)));
  const LabF cast = plain.Lab(150, static_cast<uint8_t>(g), 150);
  const LabF neutral = balanced.Lab(150, static_cast<uint8_t>(g), 150);
  EXPECT_LT(cast.a, -20.f);
  EXPECT_NEAR(neutral.a, 0.f, 0.3f);
  EXPECT_NEAR(neutral.b, 0.f, 0.3f);
  EXPECT_NEAR(neutral.L, plain.L(150, 150, 150), 0.3f);
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
