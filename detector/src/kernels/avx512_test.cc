#include "kernels/avx512.h"

#include <gtest/gtest.h>

#include <vector>

#include "kernels/color_table.h"
#include "kernels/kernels.h"

namespace chromatag::internal {
namespace {

#ifdef CHROMATAG_HAVE_X86_KERNELS
// A row of 256 samples at N = 4 (every fourth pixel of `row`).
RowSampler EveryFourthPixel(const std::vector<uint8_t>& row, int r_offset, int b_offset) {
  RowSampler sampler;
  sampler.row = row.data();
  sampler.row_bytes = static_cast<int>(row.size());
  sampler.count = 256;
  sampler.pixel_step = 12;
  sampler.r = r_offset;
  sampler.b = b_offset;
  return sampler;
}

// The AVX-512 row scan computes exactly ColorTable::FastA, for every one of
// the 16.7 million colours (a row per red and green level, one sample per
// blue level at N = 4), in both pixel orders for some red levels.
TEST(Avx512KernelTest, ComputedAIsFastAForEveryColour) {
  if (!Kernels::Available(KernelPath::kAvx512)) GTEST_SKIP() << "this CPU has no AVX-512 with VBMI";
  const ColorTable& table = ColorTable::Get();
  std::vector<uint8_t> row(12 * 256, 0);
  std::vector<int16_t> a(256);
  long mismatches = 0;
  for (int red = 0; red < 256; ++red) {
    for (int r_offset : {2, 0}) {
      if (r_offset == 0 && red % 51 != 0) continue;
      const int b_offset = 2 - r_offset;
      for (int green = 0; green < 256; ++green) {
        for (int blue = 0; blue < 256; ++blue) {
          row[12 * blue + r_offset] = static_cast<uint8_t>(red);
          row[12 * blue + 1] = static_cast<uint8_t>(green);
          row[12 * blue + b_offset] = static_cast<uint8_t>(blue);
        }
        const RowSampler sampler = EveryFourthPixel(row, r_offset, b_offset);
        ComputedARowAvx512(sampler, table.fast_a_tables(), a.data());
        for (int blue = 0; blue < 256; ++blue) {
          if (a[blue] != table.FastA(red, green, blue) && ++mismatches <= 5) {
            ADD_FAILURE() << "colour (" << red << ", " << green << ", " << blue << "): kernel "
                          << a[blue] << ", FastA " << table.FastA(red, green, blue);
          }
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

// With a white balance folded into the channel weights, the kernel still
// computes exactly FastA: every green and blue level for every fifth red.
TEST(Avx512KernelTest, ComputedAIsFastAWithGains) {
  if (!Kernels::Available(KernelPath::kAvx512)) GTEST_SKIP() << "this CPU has no AVX-512 with VBMI";
  for (const ColorTable::Gains& gains :
       {ColorTable::Gains{0.6, 1.0, 0.6}, ColorTable::Gains{1.0, 0.2, 0.2},
        ColorTable::Gains{0.2, 0.2, 1.0}}) {
    const ColorTable table(gains);
    std::vector<uint8_t> row(12 * 256, 0);
    std::vector<int16_t> a(256);
    long mismatches = 0;
    for (int red = 0; red < 256; red += 5) {
      for (int green = 0; green < 256; ++green) {
        for (int blue = 0; blue < 256; ++blue) {
          row[12 * blue + 2] = static_cast<uint8_t>(red);
          row[12 * blue + 1] = static_cast<uint8_t>(green);
          row[12 * blue] = static_cast<uint8_t>(blue);
        }
        const RowSampler sampler = EveryFourthPixel(row, 2, 0);
        ComputedARowAvx512(sampler, table.fast_a_tables(), a.data());
        for (int blue = 0; blue < 256; ++blue)
          mismatches += a[blue] != table.FastA(red, green, blue);
      }
    }
    EXPECT_EQ(mismatches, 0) << "gains " << gains[0] << " " << gains[1] << " " << gains[2];
  }
}
#endif

}  // namespace
}  // namespace chromatag::internal
