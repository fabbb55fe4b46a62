#include "chromatag/calib/printer_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace chromatag {
namespace {

// A printer of the model's own form with known, non-trivial parameters.
PrinterModel TruePrinter() {
  PrinterModel m;
  for (int c = 0; c < 3; ++c) {
    for (int k = 0; k < kToneSegments; ++k) m.tone[c][k] = 0.3 * std::sin(k + c) - 0.05 * k;
  }
  // Desaturate: mix each column towards grey, keep white.
  const PrinterModel identity;
  for (int i = 0; i < 3; ++i) {
    const double row =
        identity.matrix[3 * i] + identity.matrix[3 * i + 1] + identity.matrix[3 * i + 2];
    for (int j = 0; j < 3; ++j)
      m.matrix[3 * i + j] = 0.8 * identity.matrix[3 * i + j] + 0.2 * row / 3;
  }
  m.offset = {0.01, 0.012, 0.011};
  return m;
}

std::vector<PrinterSample> Samples(const PrinterModel& truth, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<PrinterSample> samples;
  for (int i = 0; i < n; ++i) {
    const Rgb rgb{u(rng), u(rng), u(rng)};
    samples.push_back({rgb, truth.Predict(rgb), i});
  }
  for (double v : {0.0, 0.25, 0.5, 0.75, 1.0})
    samples.push_back({{v, v, v}, truth.Predict({v, v, v}), -1});
  return samples;
}

TEST(PrinterModelTest, IdentityIsSrgb) {
  const PrinterModel identity;
  for (const Rgb& rgb : {Rgb{1, 1, 1}, Rgb{0.2, 0.5, 0.9}, Rgb{0.9, 0.1, 0.3}}) {
    const Lab expected = SrgbToLab(rgb);
    const Lab got = identity.Predict(rgb);
    EXPECT_NEAR(got.L, expected.L, 1e-6);
    EXPECT_NEAR(got.a, expected.a, 1e-6);
    EXPECT_NEAR(got.b, expected.b, 1e-6);
  }
}

TEST(PrinterModelTest, FitRecoversAKnownPrinterDespiteOutliers) {
  const PrinterModel truth = TruePrinter();
  std::vector<PrinterSample> samples = Samples(truth, 150, 1);
  // Ten patches ruined by glare: far lighter than the model.
  for (int i = 0; i < 10; ++i)
    samples[i * 7].measured.L = std::min(100.0, samples[i * 7].measured.L + 25);
  std::string error;
  const auto fit = FitPrinterModel(samples, {}, &error);
  ASSERT_TRUE(fit) << error;
  // On new colours the fitted model predicts the truth closely.
  double worst = 0;
  for (const PrinterSample& s : Samples(truth, 100, 2))
    worst = std::max(worst, Ciede2000(fit->model.Predict(s.sent), s.measured));
  EXPECT_LT(worst, 1.0);
  EXPECT_EQ(fit->residual_de.size(), samples.size());
  EXPECT_GT(fit->max_de, 10.0);  // The glare patches stand out.
}

TEST(PrinterModelTest, InversionFindsTheRgbThatPrintsATarget) {
  const std::vector<PrinterModel> models = {TruePrinter()};
  for (const Rgb& rgb : {Rgb{0.8, 0.2, 0.3}, Rgb{0.3, 0.6, 0.4}, Rgb{0.5, 0.5, 0.5}}) {
    const Lab target = models[0].Predict(rgb);
    const Rgb found = InvertPrinter(models, target, Rgb{0.5, 0.5, 0.5});
    EXPECT_LT(Ciede2000(models[0].Predict(found), target), 0.05);
  }
  // Out of reach: the nearest printable colour, inside the cube.
  const Rgb found = InvertPrinter(models, Lab{50, 120, 0}, Rgb{1, 0, 0.5});
  for (double v : {found.r, found.g, found.b}) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

TEST(PrinterModelTest, TooFewSamplesAreRefused) {
  std::string error;
  EXPECT_FALSE(FitPrinterModel(Samples(TruePrinter(), 5, 3), {}, &error));
  EXPECT_NE(error.find("need 20"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag
