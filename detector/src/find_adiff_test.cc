#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "find_adiff.h"

#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace chromatag::internal {
namespace {

// BGR: grey a* = 0, green a* far below it, red far above.
const cv::Scalar kGrey(128, 128, 128), kGreen(70, 160, 40), kRed(50, 40, 200);

// Columns [x0, x1) and rows [y0, y1) of each drawn rectangle.
struct Box {
  int x0, y0, x1, y1;
  bool HasRow(int y) const { return y0 <= y && y < y1; }
};
constexpr Box kGreenBox{37, 30, 161, 150}, kRedBox{70, 61, 131, 119};
// Wide enough for odd sample counts and the vector paths' tails.
const cv::Size kFrame(203, 180);

cv::Mat RenderScene() {
  cv::Mat image(kFrame, CV_8UC3, kGrey);
  for (const auto& [box, colour] : {std::pair(kGreenBox, kGreen), std::pair(kRedBox, kRed)}) {
    cv::rectangle(image, cv::Rect(box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0), colour,
                  cv::FILLED);
  }
  return image;
}

// The first sampled column at or after x.
int FirstSampleFrom(int x, int step) { return (x + step - 1) / step * step; }

// Every seed FindADiff returns on row y, in order.
std::vector<cv::Point> Seeds(const ImageView& view, const DetectorOptions& options,
                             const std::vector<DetectedArea>& skip, int y,
                             std::vector<Seed>* kinds = nullptr) {
  RowCursor cursor;
  cursor.y = y;
  std::vector<cv::Point> seeds;
  cv::Point seed;
  Seed kind = Seed::kNone;
  int rejects = 0;
  RowScanBuffers buffers;
  while (FindADiff(view, options, skip, &buffers, &cursor, &seed, &kind, &rejects)) {
    EXPECT_NE(kind, Seed::kNone);
    seeds.push_back(seed);
    if (kinds) kinds->push_back(kind);
  }
  return seeds;
}

class FindADiffTest : public testing::TestWithParam<int> {
 protected:
  DetectorOptions Options() const {
    DetectorOptions options;
    options.step = GetParam();
    return options;
  }
};

// On each sampled row the seeds are the first samples past the rises in a*:
// green to red where the row crosses the red, green to grey on the green's
// right. Grey to green and red to green fall and give none.
TEST_P(FindADiffTest, SeedsAtTheRisesInA) {
  const cv::Mat image = RenderScene();
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  for (int y = 0; y < image.rows; y += options.step) {
    std::vector<cv::Point> expected;
    if (kRedBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kRedBox.x0, options.step), y);
    if (kGreenBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kGreenBox.x1, options.step), y);
    EXPECT_EQ(Seeds(view, options, {}, y), expected) << "row " << y;
  }
}

// A flat frame has no seeds on any row.
TEST_P(FindADiffTest, FlatFrameHasNoSeeds) {
  const cv::Mat image(kFrame, CV_8UC3, kGrey);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  for (int y = 0; y < image.rows; y += options.step) {
    EXPECT_TRUE(Seeds(view, options, {}, y).empty()) << "row " << y;
  }
}

// An accepted area over the red suppresses its seeds and no others.
TEST_P(FindADiffTest, SkipsDetectedAreas) {
  const cv::Mat image = RenderScene();
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const DetectorOptions options = Options();
  DetectedArea area;
  const double x0 = kRedBox.x0 - 4, x1 = kRedBox.x1 + 4;
  area.min_y = kRedBox.y0 - 4;
  area.max_y = kRedBox.y1 + 4;
  area.quad = {{{x0, area.min_y}, {x1, area.min_y}, {x1, area.max_y}, {x0, area.max_y}}};
  for (int y = 0; y < image.rows; y += options.step) {
    std::vector<cv::Point> expected;
    if (kGreenBox.HasRow(y)) expected.emplace_back(FirstSampleFrom(kGreenBox.x1, options.step), y);
    EXPECT_EQ(Seeds(view, options, {area}, y), expected) << "row " << y;
  }
}

INSTANTIATE_TEST_SUITE_P(Steps, FindADiffTest, testing::Values(1, 3, 4, 5, 8));

// An 8 x 120 image of vertical stripes: each (end, colour) paints the
// columns up to `end` (exclusive) from the previous stripe's end.
cv::Mat Stripes(const std::vector<std::pair<int, Rgb8>>& stripes) {
  cv::Mat image(8, 120, CV_8UC3);
  int x = 0;
  for (const auto& [end, c] : stripes) {
    for (; x < end; ++x) {
      for (int y = 0; y < image.rows; ++y) image.at<cv::Vec3b>(y, x) = {c.b, c.g, c.r};
    }
  }
  return image;
}

// A red/green border blurred over two samples: green (a* -12), a blend
// (a* 6) for one sample, then red (a* 28). Neither step passes ADiffThresh
// 25; the rise over both, from green, seeds with two_step_rises, at the
// first red sample, and only there. Steps from grey do not.
TEST(FindADiffTwoStepTest, SeedsWhereTheRiseFromGreenTakesTwoSamples) {
  const Rgb8 green = LabToSrgb8({50, -12, 10}), blend = LabToSrgb8({50, 6, 10}),
             red = LabToSrgb8({50, 28, 10}), grey = LabToSrgb8({50, 0, 0});
  // Green to red at 40-47 and 100-107 from green, grey to red at 72-79.
  const cv::Mat image = Stripes({{40, green},
                                 {44, blend},
                                 {64, red},
                                 {72, grey},
                                 {76, blend},
                                 {92, red},
                                 {100, green},
                                 {104, blend},
                                 {120, red}});
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  for (bool two_step : {false, true}) {
    DetectorOptions options;
    options.two_step_rises = two_step;
    const std::vector<cv::Point> seeds = Seeds(view, options, {}, 4);
    if (two_step) {
      EXPECT_EQ(seeds, (std::vector<cv::Point>{{44, 4}, {104, 4}}));
    } else {
      EXPECT_TRUE(seeds.empty()) << seeds.size();
    }
  }
}

// The same rise over two samples under what a cast and dim light do to a*:
// from a green a magenta cast lifted to a* 1, and up to a faded red a green
// cast and dim light left at a* 10. Each seeds, as a seed that must show a
// tag's colours in its own light (Seed::kInACast); the rise from a true
// green to a true red is an ordinary seed.
TEST(FindADiffTwoStepTest, RisesThatOnlyACastExplainsAreSeedsInACast) {
  const Rgb8 cast_green = LabToSrgb8({50, 1, 10}), cast_blend = LabToSrgb8({50, 15, 10}),
             red = LabToSrgb8({50, 30, 10}), green = LabToSrgb8({40, -20, 10}),
             pale_blend = LabToSrgb8({40, -5, 10}), pale_red = LabToSrgb8({40, 10, 10});
  // A cast green to red at 20-27, a green to a pale red at 60-67, a green
  // to a red at 100-107.
  const cv::Mat image = Stripes({{20, cast_green},
                                 {24, cast_blend},
                                 {40, red},
                                 {60, green},
                                 {64, pale_blend},
                                 {80, pale_red},
                                 {100, green},
                                 {104, pale_blend},
                                 {120, red}});
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  std::vector<Seed> kinds;
  DetectorOptions in_casts;
  in_casts.cast_seeds = true;
  EXPECT_EQ(Seeds(view, in_casts, {}, 4, &kinds),
            (std::vector<cv::Point>{{24, 4}, {64, 4}, {104, 4}}));
  EXPECT_EQ(kinds, (std::vector<Seed>{Seed::kInACast, Seed::kInACast, Seed::kSeed}));
  // Without cast_seeds (the default) the rise from the lifted green is
  // none; the one into the pale red still seeds in a cast.
  kinds.clear();
  EXPECT_EQ(Seeds(view, DetectorOptions{}, {}, 4, &kinds),
            (std::vector<cv::Point>{{64, 4}, {104, 4}}));
  EXPECT_EQ(kinds, (std::vector<Seed>{Seed::kInACast, Seed::kSeed}));
}

// Dim light: a rise over two samples from green into a red darker than
// kDimTwoStepMaxL seeds above kDimTwoStepShare of ADiffThresh, as a seed that
// must show a tag's colours in its own light, however red the red (an
// ordinary seed needs the whole ADiffThresh); below that share, or in
// lighter colours, it does not seed. On every kernel path.
TEST(FindADiffTwoStepTest, InDimLightALowerRiseSeeds) {
  const ColorTable& table = ColorTable::Get();
  const DetectorOptions options;
  const float thresh = static_cast<float>(options.adiff_thresh);
  struct Case {
    float lightness, green_a, blend_a, red_a;
    bool seeds;
  };
  // Rises of a* 24 (a pale red, and a red of a* 18 and more) and 21.5.
  for (const Case& c : {Case{30, -12.5f, 0, 11.5f, true}, Case{30, -6, 6, 18.5f, true},
                        Case{30, -6, 4, 15.5f, false}, Case{55, -12.5f, 0, 11.5f, false}}) {
    const Rgb8 green = LabToSrgb8({c.lightness, c.green_a, 10}),
               blend = LabToSrgb8({c.lightness, c.blend_a, 10}),
               red = LabToSrgb8({c.lightness, c.red_a, 10});
    // The colours as the detector reads them: each step over kTwoStepShare
    // of ADiffThresh, the rise under ADiffThresh and on the case's side of
    // the dim light's bar.
    auto a_of = [&](const Rgb8& v) { return table.A(v.r, v.g, v.b); };
    const float rise = a_of(red) - a_of(green);
    const auto where = testing::Message() << "L* " << c.lightness << ", rise " << rise;
    ASSERT_LT(rise, thresh) << where;
    ASSERT_EQ(rise > kDimTwoStepShare * thresh, c.seeds || c.lightness >= kDimTwoStepMaxL) << where;
    ASSERT_GT(a_of(blend) - a_of(green), kTwoStepShare * thresh) << where;
    ASSERT_GT(a_of(red) - a_of(blend), kTwoStepShare * thresh) << where;
    ASSERT_EQ(table.L(red.r, red.g, red.b) < kDimTwoStepMaxL, c.lightness < kDimTwoStepMaxL)
        << where;
    const cv::Mat image = Stripes({{40, green}, {44, blend}, {120, red}});
    for (KernelPath path : {KernelPath::kAvx512, KernelPath::kAvx2, KernelPath::kScalar}) {
      if (!Kernels::Available(path)) continue;
      const ImageView view(image, PixelOrder::kBgr, table, Kernels::ForPath(path));
      std::vector<Seed> kinds;
      const std::vector<cv::Point> seeds = Seeds(view, options, {}, 4, &kinds);
      if (c.seeds) {
        EXPECT_EQ(seeds, (std::vector<cv::Point>{{44, 4}})) << where << ", path " << int(path);
        EXPECT_EQ(kinds, (std::vector<Seed>{Seed::kInACast})) << where << ", path " << int(path);
      } else {
        EXPECT_TRUE(seeds.empty()) << where << ", path " << int(path) << ": " << seeds.size();
      }
    }
  }
}

// The kernel's luminance gate for the dim light's bar (ComputedDimYLimit)
// lets through every colour darker than kDimTwoStepMaxL by the accurate L*,
// with the default table and with white balances folded in; and it is a
// gate: most colours of L* 50 and up are kept out.
TEST(FindADiffTwoStepTest, DimGateLetsEveryDimColourThrough) {
  const int limit = ComputedDimYLimit();
  for (const ColorTable::Gains& gains :
       {ColorTable::Gains{1.0, 1.0, 1.0}, ColorTable::Gains{0.6, 1.0, 1.0},
        ColorTable::Gains{1.0, 0.7, 0.5}, ColorTable::Gains{0.5, 0.6, 1.0}}) {
    const ColorTable table(gains);
    // L* below a level exactly when Y is below YForL of it.
    const int32_t dim_y = table.YForL(kDimTwoStepMaxL), light_y = table.YForL(50.f);
    long dim = 0, dim_kept_out = 0, light = 0, light_let_through = 0;
    for (int r = 0; r < 256; ++r) {
      for (int g = 0; g < 256; ++g) {
        for (int b = 0; b < 256; ++b) {
          const int32_t y = table.Y(r, g, b);
          const bool below = table.FastY(r, g, b) < limit;
          if (y < dim_y) {
            ++dim;
            dim_kept_out += !below;
          } else if (y >= light_y) {
            ++light;
            light_let_through += below;
          }
        }
      }
    }
    const auto where = testing::Message()
                       << "gains " << gains[0] << " " << gains[1] << " " << gains[2];
    EXPECT_GT(dim, 0) << where;
    EXPECT_EQ(dim_kept_out, 0) << where;
    EXPECT_LT(light_let_through, light / 100) << where;
  }
}

// Rows of random colours, many short runs and some long ones, at widths
// that end each of the vector paths' blocks anywhere.
cv::Mat RandomRows(int width, cv::RNG* rng) {
  cv::Mat image(9, width, CV_8UC3);
  for (int y = 0; y < image.rows; ++y) {
    cv::Vec3b colour;
    for (int x = 0; x < width; ++x) {
      if (x == 0 || rng->uniform(0, y + 1) == 0) {
        // Extremes too: the computed a*'s tables end at 0 and 255.
        for (int c = 0; c < 3; ++c)
          colour[c] = rng->uniform(0, 4) == 0 ? 255 * rng->uniform(0, 2) : rng->uniform(0, 256);
      }
      image.at<cv::Vec3b>(y, x) = colour;
    }
  }
  return image;
}

// Every kernel path lists every sample that seeds by the accurate a*
// (SeedsAt: a rise by more than ADiffThresh, in one step or in two from
// green), each once and in order; where a* is computed (AVX-512), exactly
// the samples that seed by ColorTable::FastA with its thresholds, so that
// the vector code is its scalar reference.
TEST(ScanRowTest, EveryPathListsEveryTrueRise) {
  cv::RNG rng(17);
  int paths_run = 0, true_rises = 0;
  // The default table, and one with a white balance folded in (for a third
  // of the widths: the gains move the luminance the dim light's bar reads).
  const ColorTable gained(ColorTable::Gains{0.6, 1.0, 0.8});
  for (KernelPath path : {KernelPath::kAvx512, KernelPath::kAvx2, KernelPath::kScalar}) {
    if (!Kernels::Available(path)) continue;
    const Kernels& kernels = Kernels::ForPath(path);
    ++paths_run;
    for (int width : {1, 2, 4, 5, 124, 125, 128, 129, 131, 255, 256, 257, 383, 752}) {
      const cv::Mat image = RandomRows(width, &rng);
      const ColorTable& table = width % 3 == 0 ? gained : ColorTable::Get();
      for (PixelOrder order : {PixelOrder::kBgr, PixelOrder::kRgb}) {
        const ImageView view(image, order, table, kernels);
        const int ri = order == PixelOrder::kBgr ? 2 : 0, bi = 2 - ri;
        for (double adiff : {8.0, 25.0, 60.0}) {
          for (bool two_step_rises : {false, true}) {
            DetectorOptions options;
            options.step = 4;
            options.adiff_thresh = adiff;
            options.two_step_rises = two_step_rises;
            // The cast levels on half the rows' widths, the strict ones on
            // the others.
            options.cast_seeds = width % 2 == 0;
            const int count = (width + 3) / 4;
            for (int y = 0; y < image.rows; ++y) {
              std::vector<int32_t> coarse(count);
              std::vector<int> rises(count);
              rises.resize(ScanRow(view, options, y, coarse.data(), rises.data()));
              const auto* row = image.ptr<uint8_t>(y);
              std::vector<int> exact, computed;
              auto a_at = [&](int i) {
                const uint8_t* p = row + 12 * i;
                return table.A(p[ri], p[1], p[bi]);
              };
              auto fast_at = [&](int i) {
                const uint8_t* p = row + 12 * i;
                return static_cast<int>(table.FastA(p[ri], p[1], p[bi]));
              };
              const int thresh = ComputedARiseThreshold(adiff);
              const int step_thresh = ComputedARiseThreshold(kTwoStepShare * adiff);
              const int dim_thresh = ComputedARiseThreshold(kDimTwoStepShare * adiff);
              for (int i = 1; i < count; ++i) {
                const float two_before = i >= 2 ? a_at(i - 2) : std::nanf("");
                const uint8_t* p = row + 12 * i;
                if (SeedsAt(options, table.Lab(p[ri], p[1], p[bi]), a_at(i - 1), two_before) !=
                    Seed::kNone)
                  exact.push_back(i);
                auto sat = [](int v) { return std::clamp(v, -32768, 32767); };
                const int rise = sat(fast_at(i) - fast_at(i - 1));
                const bool two_step = options.two_step_rises && i >= 2 &&
                                      fast_at(i - 2) < ComputedAGreenLimit(options) &&
                                      fast_at(i) > ComputedATwoStepRedFloor() &&
                                      (sat(fast_at(i) - fast_at(i - 2)) > thresh ||
                                       (sat(fast_at(i) - fast_at(i - 2)) > dim_thresh &&
                                        table.FastY(p[ri], p[1], p[bi]) < ComputedDimYLimit())) &&
                                      rise > step_thresh &&
                                      sat(fast_at(i - 1) - fast_at(i - 2)) > step_thresh;
                if (rise > thresh || two_step) computed.push_back(i);
              }
              true_rises += exact.size();
              const auto where = testing::Message()
                                 << "path " << static_cast<int>(path) << " width " << width
                                 << " row " << y << " ADiffThresh " << adiff << " two-step "
                                 << options.two_step_rises;
              EXPECT_TRUE(std::is_sorted(rises.begin(), rises.end())) << where;
              EXPECT_EQ(std::adjacent_find(rises.begin(), rises.end()), rises.end()) << where;
              EXPECT_TRUE(std::includes(rises.begin(), rises.end(), exact.begin(), exact.end()))
                  << where;
              if (RowScanComputesA(view, options)) {
                EXPECT_EQ(rises, computed) << where;
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GE(paths_run, 1);  // kScalar runs anywhere.
  if (!Kernels::Available(KernelPath::kAvx512)) {
    std::printf("this CPU has no AVX-512 with VBMI: that path was not tested\n");
  }
  EXPECT_GT(true_rises, 1000);
}

#ifdef __linux__
// No path reads a byte past the row: each row is placed against a page
// that may not be read, so a read past it faults (the AVX-512 path's masked
// loads of the row's last block included).
TEST(ScanRowTest, ReadsNothingPastTheRow) {
  const long page = sysconf(_SC_PAGESIZE);
  const size_t length = 2 * static_cast<size_t>(page);
  void* memory = mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(memory, MAP_FAILED);
  auto* guard = static_cast<uint8_t*>(memory) + page;
  ASSERT_EQ(mprotect(guard, page, PROT_NONE), 0);
  cv::RNG rng(5);
  const ColorTable& table = ColorTable::Get();
  int runs = 0;
  for (KernelPath path : {KernelPath::kAvx512, KernelPath::kAvx2, KernelPath::kScalar}) {
    if (!Kernels::Available(path)) continue;
    for (int width : {1, 2, 5, 31, 125, 128, 129, 383, 752, 1000}) {
      uint8_t* data = guard - 3 * width;
      cv::Mat image(1, width, CV_8UC3, data);
      rng.fill(image, cv::RNG::UNIFORM, 0, 256);
      for (int step : {4, 5}) {
        DetectorOptions options;
        options.step = step;
        const int count = (width + step - 1) / step;
        std::vector<int32_t> coarse(count);
        std::vector<int> rises(count);
        ScanRow(ImageView(image, PixelOrder::kBgr, table, Kernels::ForPath(path)), options, 0,
                coarse.data(), rises.data());
        ++runs;
      }
    }
  }
  munmap(memory, length);
  EXPECT_GE(runs, 20);
}
#endif

// A quad's span on a row runs between the two sides the row crosses.
TEST(DetectedAreaTest, RowSpanOfADiamond) {
  DetectedArea diamond;
  diamond.quad = {{{50, 10}, {80, 40}, {50, 70}, {20, 40}}};
  diamond.min_y = 10;
  diamond.max_y = 70;
  double begin = 0, end = 0;
  ASSERT_TRUE(diamond.RowSpan(25, &begin, &end));
  EXPECT_DOUBLE_EQ(begin, 35);
  EXPECT_DOUBLE_EQ(end, 65);
  ASSERT_TRUE(diamond.RowSpan(40, &begin, &end));
  EXPECT_DOUBLE_EQ(begin, 20);
  EXPECT_DOUBLE_EQ(end, 80);
  EXPECT_FALSE(diamond.RowSpan(5, &begin, &end));
  EXPECT_FALSE(diamond.RowSpan(71, &begin, &end));
  EXPECT_TRUE(diamond.Contains({50, 50}));
  EXPECT_TRUE(diamond.Contains({35, 40}));
  EXPECT_FALSE(diamond.Contains({35, 20}));
  EXPECT_FALSE(diamond.Contains({50, 75}));
}

}  // namespace
}  // namespace chromatag::internal
