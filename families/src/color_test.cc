#include "chromatag/families/color.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace chromatag {
namespace {

TEST(ColorTest, TransferCurveRoundTripsAndHitsKnownPoints) {
  EXPECT_DOUBLE_EQ(SrgbToLinear(0.0), 0.0);
  EXPECT_DOUBLE_EQ(SrgbToLinear(1.0), 1.0);
  EXPECT_NEAR(SrgbToLinear(0.5), 0.214041, 1e-6);
  EXPECT_NEAR(SrgbToLinear(0.04045), 0.04045 / 12.92, 1e-12);
  for (double v = -0.2; v <= 1.2; v += 0.01) {
    EXPECT_NEAR(LinearToSrgb(SrgbToLinear(v)), v, 1e-12) << v;
  }
}

TEST(ColorTest, WhiteBlackAndPrimariesHaveTheirCielabValues) {
  const Lab white = SrgbToLab(Rgb8{255, 255, 255});
  EXPECT_NEAR(white.L, 100.0, 1e-4);
  EXPECT_NEAR(white.a, 0.0, 1e-4);
  EXPECT_NEAR(white.b, 0.0, 1e-4);
  const Lab black = SrgbToLab(Rgb8{0, 0, 0});
  EXPECT_NEAR(black.L, 0.0, 1e-9);
  const Lab red = SrgbToLab(Rgb8{255, 0, 0});
  EXPECT_NEAR(red.L, 53.24, 0.01);
  EXPECT_NEAR(red.a, 80.09, 0.01);
  EXPECT_NEAR(red.b, 67.20, 0.01);
  const Lab green = SrgbToLab(Rgb8{0, 255, 0});
  EXPECT_NEAR(green.a, -86.18, 0.01);
}

// Spec section 5 names OpenCV's float cvtColor as the oracle. In OpenCV 4.x,
// COLOR_RGB2Lab on floats interpolates trilinearly in a 33^3 table over sRGB
// (measured: up to 0.43 off the formula between nodes, 0.0097 at the nodes),
// so it is exact enough only at its nodes, k / 32; COLOR_LRGB2Lab (linear RGB)
// evaluates the formula and is compared on a dense grid.
// One pixel per call: OpenCV's vectorised path for longer rows approximates
// the curve's linear segment (measured 0.029 off for dark colours), its scalar
// path does not.
double WorstDifference(const std::vector<Rgb>& inputs, int code, bool inputs_linear) {
  double worst = 0.0;
  for (const Rgb& input : inputs) {
    const cv::Mat rgb(1, 1, CV_32FC3,
                      cv::Scalar(static_cast<float>(input.r), static_cast<float>(input.g),
                                 static_cast<float>(input.b)));
    cv::Mat lab;
    cv::cvtColor(rgb, lab, code);
    const cv::Vec3f expected = lab.at<cv::Vec3f>(0, 0);
    const Lab ours = inputs_linear ? XyzToLab(LinearRgbToXyz(input)) : SrgbToLab(input);
    worst = std::max({worst, std::fabs(ours.L - expected[0]), std::fabs(ours.a - expected[1]),
                      std::fabs(ours.b - expected[2])});
  }
  return worst;
}

TEST(ColorTest, AgreesWithOpenCvFloatRgb2LabAtItsTableNodes) {
  std::vector<Rgb> nodes;
  for (int r = 0; r <= 32; ++r) {
    for (int g = 0; g <= 32; ++g) {
      for (int b = 0; b <= 32; ++b) nodes.push_back({r / 32.0, g / 32.0, b / 32.0});
    }
  }
  EXPECT_LE(WorstDifference(nodes, cv::COLOR_RGB2Lab, false), 0.01);
}

TEST(ColorTest, AgreesWithOpenCvFloatLinearRgb2LabOnEvery8BitStep) {
  // Every 8-bit sRGB value on each axis, on a 52^3 grid, through our transfer
  // curve: this covers the formula itself and the curve's linear segment.
  std::vector<Rgb> linear;
  for (int r = 0; r < 256; r += 5) {
    for (int g = 0; g < 256; g += 5) {
      for (int b = 0; b < 256; b += 5) {
        linear.push_back(SrgbToLinear(ToRgb(
            Rgb8{static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b)})));
      }
    }
  }
  for (int v = 0; v < 256; ++v)
    linear.push_back(SrgbToLinear(Rgb{v / 255.0, v / 255.0, v / 255.0}));
  EXPECT_LE(WorstDifference(linear, cv::COLOR_LRGB2Lab, true), 0.01);
}

TEST(ColorTest, LabRoundTripsThroughSrgb) {
  for (int r = 0; r <= 255; r += 17) {
    for (int g = 0; g <= 255; g += 17) {
      for (int b = 0; b <= 255; b += 17) {
        const Rgb8 rgb{static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b)};
        const Lab lab = SrgbToLab(rgb);
        EXPECT_TRUE(InSrgbGamut(lab));
        EXPECT_EQ(LabToSrgb8(lab), rgb);
      }
    }
  }
}

TEST(ColorTest, GamutTestRefusesColoursOutsideSrgb) {
  EXPECT_TRUE(InSrgbGamut({50.0, 0.0, 0.0}));
  EXPECT_FALSE(InSrgbGamut({50.0, -100.0, 0.0}));  // Greener than sRGB green.
  EXPECT_FALSE(InSrgbGamut({95.0, 0.0, -60.0}));
}

TEST(ColorTest, HexFormatting) { EXPECT_EQ(ToHex(Rgb8{255, 0, 16}), "#ff0010"); }

struct Ciede2000Pair {
  Lab lab1, lab2;
  double expected;
};

std::vector<Ciede2000Pair> LoadSharmaPairs() {
  std::ifstream file(std::string(CHROMATAG_TEST_DATA_DIR) + "/ciede2000_sharma2005.csv");
  std::vector<Ciede2000Pair> pairs;
  std::string line;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream stream(line);
    double v[7];
    char comma;
    stream >> v[0];
    for (int i = 1; i < 7; ++i) stream >> comma >> v[i];
    pairs.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6]});
  }
  return pairs;
}

TEST(ColorTest, Ciede2000MatchesSharmaWuDalalTestData) {
  const auto pairs = LoadSharmaPairs();
  ASSERT_EQ(pairs.size(), 34u);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const auto& p = pairs[i];
    EXPECT_NEAR(Ciede2000(p.lab1, p.lab2), p.expected, 5e-5) << "pair " << i + 1;
    EXPECT_NEAR(Ciede2000(p.lab2, p.lab1), p.expected, 5e-5) << "pair " << i + 1 << " swapped";
  }
}

TEST(ColorTest, Ciede2000IsZeroOnlyForEqualColoursAndHonoursWeights) {
  const Lab a{52.0, 10.0, -30.0};
  EXPECT_EQ(Ciede2000(a, a), 0.0);
  const Lab light{80.0, 5.0, 5.0}, dark{50.0, 5.0, 5.0};
  // Pure lightness difference: doubling kL halves the difference.
  EXPECT_NEAR(Ciede2000(light, dark, 2.0), Ciede2000(light, dark) / 2.0, 1e-12);
}

}  // namespace
}  // namespace chromatag
