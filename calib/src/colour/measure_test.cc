// Measuring synthetic photos of a printed calibration sheet: every patch's
// colour against the simulated truth.
#include <gtest/gtest.h>

#include "calib_sim.h"
#include "chromatag/calib/measure.h"

namespace chromatag {
namespace {

using testing::CameraReferredTruth;
using testing::RenderSheetPhoto;
using testing::SimCamera;
using testing::SimPrinter;

CalibSheetLayout Sheet() {
  CalibSheetOptions options;
  options.palette = *BuiltinPalette("default");
  return *LayoutCalibSheet(options);
}

TEST(CalibMeasureTest, ColorimetricCameraMeasuresThePrintWithinTwoDeltaE) {
  const CalibSheetLayout layout = Sheet();
  const SimPrinter printer;
  SimCamera camera;
  camera.gains = {1.1, 1.0, 0.8};  // Warm light.
  const cv::Mat photo = RenderSheetPhoto(layout, printer, camera);
  std::string error;
  const auto m = MeasurePhoto(photo, layout, {}, {}, &error);
  ASSERT_TRUE(m) << error;
  double worst = 0;
  int used = 0;
  for (const Patch& p : layout.patches) {
    const PatchMeasurement& pm = m->patches[p.index];
    if (!pm.usable()) continue;
    ++used;
    const Lab truth = printer.Print(p.rgb);
    const double de = Ciede2000(pm.lab, truth);
    worst = std::max(worst, de);
    EXPECT_LT(de, 2.0) << "patch " << p.index << " " << PatchKindName(p.kind) << " measured "
                       << pm.lab.L << " " << pm.lab.a << " " << pm.lab.b << " truth " << truth.L
                       << " " << truth.a << " " << truth.b;
  }
  EXPECT_GT(used, static_cast<int>(layout.patches.size() * 9 / 10));
  std::printf("worst CIEDE2000 %.2f over %d patches, %.2f px/mm\n", worst, used,
              m->location.px_per_mm);
}

}  // namespace
}  // namespace chromatag
