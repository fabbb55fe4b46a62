// The camera set's printers and their calibrated detector configs (prints.h).
#include "chromatag/bench/prints.h"

#include <algorithm>
#include <memory>

#include "calib_sim.h"
#include "chromatag/calib/calib_sheet.h"
#include "chromatag/calib/calibrate.h"
#include "chromatag/families/palette.h"
#include "dataset_impl.h"
#include "icc_press.h"

namespace chromatag::bench {
namespace {

// The calibration sheet's raster, finer than the photos' 3.9 px/mm.
constexpr double kSheetPxPerMm = 6.0;

Lab PrintExactly(const Rgb8& sent, double chroma) {
  const Lab lab = SrgbToLab(sent);
  return {std::clamp(lab.L, kPrintBlackL, kPrintWhiteL), lab.a * chroma, lab.b * chroma};
}

}  // namespace

Printer MakePrinter(PrintKind kind, std::string* error) {
  switch (kind) {
    case PrintKind::kDefault:
    case PrintKind::kIccv17:
      return [](const Rgb8& sent) { return PrintExactly(sent, 1.0); };
    case PrintKind::kIccv17Faded:
      return [](const Rgb8& sent) { return PrintExactly(sent, kFadedChroma); };
    case PrintKind::kDefaultPress: {
      std::shared_ptr<const testing::IccPress> press =
          testing::IccPress::Load(testing::IccPress::DefaultCmykProfilePath(), error);
      if (!press) return {};
      return [press](const Rgb8& sent) { return press->Print(sent); };
    }
  }
  return {};
}

TagColors PrintedTagColors(PrintKind kind, const Printer& printer) {
  Palette printed = *BuiltinPalette(PrintKindPalette(kind));
  const TagColors sent = TagColors::FromPalette(printed);
  for (Shade shade : kAllShades) printed[shade] = printer(ToRgb8(sent[shade]));
  return TagColors::FromPalette(printed);
}

std::optional<DetectorOptions> CalibratedOptions(PrintKind kind, std::string* error) {
  const Printer printer = MakePrinter(kind, error);
  if (!printer) return std::nullopt;
  CalibSheetOptions sheet;
  const auto palette = BuiltinPalette(PrintKindPalette(kind), error);
  if (!palette) return std::nullopt;
  sheet.palette = *palette;
  const auto layout = LayoutCalibSheet(sheet, error);
  if (!layout) return std::nullopt;
  const cv::Mat page = RasterizeCalibPage(*layout, kSheetPxPerMm);
  std::vector<PhotoInput> photos;
  for (const testing::NamedCamera& light : testing::TungstenAndDaylight()) {
    photos.push_back({light.name + ".png",
                      testing::PrintAndPhotograph(page, kSheetPxPerMm, printer, {}, light.camera)});
  }
  const auto result = Calibrate(*layout, photos, {}, error);
  if (!result) return std::nullopt;
  return result->thresholds.options;
}

}  // namespace chromatag::bench
