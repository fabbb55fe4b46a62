// The whole calibration on synthetic photos of a printed sheet: thresholds
// that find washed-out tags, a LUT that corrects the printer, a palette
// chosen from the candidates, and photos that must be refused.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "calib_sim.h"
#include "chromatag/calib/calibrate.h"
#include "chromatag/calib/report.h"
#include "chromatag/detector/config.h"
#include "chromatag/detector/detector.h"
#include "chromatag/generator/color_lut.h"
#include "icc_press.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

using testing::CameraReferredTruth;
using testing::RenderPrintedTag;
using testing::RenderSheetPhoto;
using testing::SimCamera;
using testing::SimPrinter;

CalibSheetLayout Sheet(const std::string& palette = "default", int sheet_id = 0) {
  CalibSheetOptions options;
  options.palette = *BuiltinPalette(palette);
  options.sheet_id = sheet_id;
  return *LayoutCalibSheet(options);
}

// Two photos of one print: warm light with a mild keystone, and cool (or,
// with `cool` false, neutral) dimmer light from another angle.
std::vector<PhotoInput> TwoPhotos(const CalibSheetLayout& layout, const SimPrinter& printer,
                                  bool cool_light = true) {
  SimCamera warm;
  warm.gains = {1.1, 1.0, 0.8};
  SimCamera cool;
  cool.gains = cool_light ? cv::Vec3d(0.85, 1.0, 1.15) : cv::Vec3d(1.0, 1.0, 1.0);
  cool.exposure = cool_light ? 0.7 : 0.8;
  cool.falloff = cool_light ? 0.3 : 0.2;
  cool.seed = 2;
  cool.page_corners_px = {{{560, 90}, {1180, 60}, {1130, 1140}, {520, 1170}}};
  return {{"warm.png", RenderSheetPhoto(layout, printer, warm)},
          {"cool.png", RenderSheetPhoto(layout, printer, cool)}};
}

std::string TempDir() {
  const std::string dir =
      std::filesystem::temp_directory_path() / ("chromatag-calib-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

TEST(CalibCalibrateTest, CameraWithMatrixAndGammaMeasuresWhatItCanSee) {
  const CalibSheetLayout layout = Sheet();
  const SimPrinter printer;
  SimCamera camera;
  camera.matrix = {0.9, 0.08, 0.02, 0.05, 0.9, 0.05, 0.02, 0.1, 0.88};
  camera.gamma = 2.2;
  camera.exposure = 0.7;
  camera.gains = {0.9, 1.0, 1.2};
  camera.blur_sigma_px = 1.0;
  camera.noise_sigma = 2.5;
  std::string error;
  const auto m = MeasurePhoto(RenderSheetPhoto(layout, printer, camera), layout, {}, {}, &error);
  ASSERT_TRUE(m) << error;
  int used = 0;
  for (const Patch& p : layout.patches) {
    const PatchMeasurement& pm = m->patches[p.index];
    if (!pm.usable()) continue;
    ++used;
    const Lab truth = CameraReferredTruth(printer.Print(p.rgb), camera);
    EXPECT_LT(Ciede2000(pm.lab, truth), 2.0) << "patch " << p.index;
  }
  EXPECT_GT(used, static_cast<int>(layout.patches.size()) * 9 / 10);
}

TEST(CalibCalibrateTest, FullRunWritesLoadableOutputs) {
  const CalibSheetLayout layout = Sheet();
  const SimPrinter printer;
  std::string error;
  const auto result = Calibrate(layout, TwoPhotos(layout, printer), {}, &error);
  ASSERT_TRUE(result) << error;
  ASSERT_EQ(result->photos.size(), 2u);
  for (const PhotoResult& p : result->photos) {
    std::printf("%s: fit mean %.2f max %.2f, %d iterations; a gap %.1f/%.1f b %.1f %.1f\n",
                p.name.c_str(), p.fit.mean_de, p.fit.max_de, p.fit.iterations, p.normalised.a_gap,
                p.seen.a_gap, p.normalised.red_b_gap, p.normalised.green_b_gap);
    EXPECT_LT(p.fit.mean_de, 2.0);
  }
  const DetectorOptions& d = result->thresholds.options;
  std::printf("adiff %.1f border %.1f margin %.2f; palette score %.2f vs %.2f\n", d.adiff_thresh,
              d.border_thresh, d.min_decision_margin, result->palette ? result->palette->score : -1,
              result->palette ? result->palette->sheet_palette_score : -1);
  for (const auto& w : result->warnings) std::printf("warning: %s\n", w.c_str());
  ASSERT_TRUE(result->palette) << result->palette_error;
  EXPECT_GE(result->palette->score, result->palette->sheet_palette_score);

  // The report: no label over another (once "0 flaggedmodel", the
  // legend's swatch over its label), on an A4 page.
  for (const std::string& overlap : ReportOverlaps(*result)) ADD_FAILURE() << overlap;
  const std::string pdf = RenderReportPdf(*result);
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 595.275591 841.889764 ]"), std::string::npos);

  const std::string dir = TempDir();
  ASSERT_TRUE(WriteFilesAtomically(CalibrationFiles(*result, dir), &error)) << error;
  DetectorOptions loaded;
  ASSERT_TRUE(LoadDetectorConfig(dir + "/detector.json", &loaded, &error)) << error;
  EXPECT_DOUBLE_EQ(loaded.adiff_thresh, d.adiff_thresh);
  EXPECT_DOUBLE_EQ(loaded.border_thresh, d.border_thresh);
  EXPECT_DOUBLE_EQ(loaded.min_decision_margin, d.min_decision_margin);
  EXPECT_DOUBLE_EQ(loaded.max_green_a, d.max_green_a);
  EXPECT_EQ(loaded.two_step_rises, d.two_step_rises);
  // Warm and cool light: no white balance fits both (the test below).
  EXPECT_EQ(loaded.white_balance, (std::array<double, 3>{1.0, 1.0, 1.0}));
  EXPECT_TRUE(LoadPaletteFile(dir + "/palette.json", &error)) << error;
  EXPECT_TRUE(ColorLut::Load(dir + "/printer.cube", &error)) << error;
  std::filesystem::remove_all(dir);
}

// max_green_a: the worst green's a* plus a quarter of the a* gap (safety
// factor 2), never below the detector's default; greens under a warm or
// magenta cast, measured redder than a* 0, raise it.
TEST(CalibCalibrateTest, MaxGreenAFollowsTheGreensMeasuredA) {
  Margins neutral;
  neutral.a_gap = 95.0;
  neutral.max_green_a = -40.0;
  neutral.red_decision = neutral.green_decision = 10.0;
  Margins cast = neutral;
  cast.a_gap = 60.0;
  cast.max_green_a = 6.0;
  EXPECT_DOUBLE_EQ(DeriveThresholds({neutral}).options.max_green_a, DetectorOptions{}.max_green_a);
  // The worst over photos: the cast one.
  EXPECT_DOUBLE_EQ(DeriveThresholds({neutral, cast}).options.max_green_a, 6.0 + 60.0 / 4.0);
  ThresholdOptions careful;
  careful.safety_factor = 3.0;
  EXPECT_DOUBLE_EQ(DeriveThresholds({cast}, careful).options.max_green_a, 16.0);
}

// ADiffThresh: the a* gap as it would be in a third of the photos' light
// (a* follows the cube root of the light), over the safety factor; never
// above the detector's default, nor is the decision margin: a stricter
// config would lose tags in dimmer light than the photos'.
TEST(CalibCalibrateTest, ThresholdsAllowForDimmerLightAndNeverExceedTheDefaults) {
  Margins washed;
  washed.a_gap = 40.0;
  washed.max_green_a = -10.0;
  washed.red_decision = washed.green_decision = 2.4;
  const DetectorOptions d = DeriveThresholds({washed}).options;
  EXPECT_NEAR(d.adiff_thresh, std::round(40.0 * std::cbrt(0.3) / 2.0 * 10.0) / 10.0, 1e-9);
  EXPECT_DOUBLE_EQ(d.min_decision_margin, 1.2);
  EXPECT_TRUE(d.two_step_rises);
  ThresholdOptions bright;
  bright.dimmest_light = 1.0;
  EXPECT_DOUBLE_EQ(DeriveThresholds({washed}, bright).options.adiff_thresh, 20.0);

  Margins vivid = washed;
  vivid.a_gap = 115.0;
  vivid.red_decision = vivid.green_decision = 30.0;
  const DetectorOptions v = DeriveThresholds({vivid}).options;
  EXPECT_DOUBLE_EQ(v.adiff_thresh, DetectorOptions{}.adiff_thresh);
  EXPECT_DOUBLE_EQ(v.min_decision_margin, DetectorOptions{}.min_decision_margin);
  EXPECT_TRUE(v.two_step_rises);  // Blur needs it whatever the print.

  std::string error;
  ThresholdOptions bad;
  bad.dimmest_light = 0.0;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("dimmest light"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag

namespace chromatag {
namespace {

TEST(CalibCalibrateTest, WashedOutThresholdsFindTagsTheDefaultsMiss) {
  const CalibSheetLayout layout = Sheet();
  const SimPrinter printer = SimPrinter::WashedOut();
  std::string error;
  // Not in cool light: it takes the printed reds below the a* of 12 the
  // detector needs to see red at all (detector/src/initial_scan.cc).
  const auto result = Calibrate(layout, TwoPhotos(layout, printer, false), {}, &error);
  ASSERT_TRUE(result) << error;
  const DetectorOptions& derived = result->thresholds.options;
  std::printf("washed out: a gap %.1f -> adiff %.1f, border %.1f, margin %.2f\n",
              result->thresholds.worst.a_gap, derived.adiff_thresh, derived.border_thresh,
              derived.min_decision_margin);
  for (const auto& w : result->warnings) std::printf("warning: %s\n", w.c_str());
  EXPECT_LT(derived.adiff_thresh, DetectorOptions{}.adiff_thresh);
  auto with_defaults = Detector::Create(DetectorOptions{});
  auto with_derived = Detector::Create(derived);
  ASSERT_TRUE(with_defaults && with_derived);
  const auto family = TagFamily::Load("16h5");
  const TagColors sent = TagColors::FromPalette(*BuiltinPalette("default"));
  // The light of the dimmer calibration photo: the thresholds are meant for it.
  SimCamera camera;
  camera.exposure = 0.8;
  camera.falloff = 0;
  int found_default = 0, found_derived = 0;
  for (int id : {0, 3, 7, 12, 19}) {
    camera.seed = id + 1;
    const cv::Mat frame = RenderPrintedTag(*family, id, sent, printer, camera, 14, 320, 240);
    for (const Detection& d : with_defaults->Detect(frame).detections) found_default += d.id == id;
    for (const Detection& d : with_derived->Detect(frame).detections) found_derived += d.id == id;
  }
  EXPECT_EQ(found_default, 0);
  EXPECT_EQ(found_derived, 5);
}

// Mean CIEDE2000 between the palette's targets and what `printer` prints for
// the palette's colours sent through `lut` (or as they are).
double MeanPrintError(const Palette& palette, const SimPrinter& printer, const ColorLut* lut,
                      bool chromatic_only) {
  double sum = 0;
  int n = 0;
  for (Shade shade : kAllShades) {
    if (chromatic_only && (shade == Shade::kBlack || shade == Shade::kWhite)) continue;
    Rgb8 sent = palette.Srgb8(shade);
    if (lut) sent = ToRgb8(lut->Apply(ToRgb(sent)));
    sum += Ciede2000(printer.Print(sent), palette[shade]);
    ++n;
  }
  return sum / n;
}

TEST(CalibCalibrateTest, LutHalvesThePrintError) {
  for (const char* name : {"default", "iccv17"}) {
    const CalibSheetLayout layout = Sheet(name);
    const SimPrinter printer;
    std::string error;
    CalibrateOptions options;
    options.lut_size = 17;
    const auto result = Calibrate(layout, TwoPhotos(layout, printer), options, &error);
    ASSERT_TRUE(result) << error;
    const std::string dir = TempDir();
    const std::string path = dir + "/printer.cube";
    ASSERT_TRUE(WriteFilesAtomically({{path, result->cube}}, &error)) << error;
    const auto lut = ColorLut::Load(path, &error);
    ASSERT_TRUE(lut) << error;
    for (bool chromatic : {false, true}) {
      const double without = MeanPrintError(layout.palette, printer, nullptr, chromatic);
      const double with = MeanPrintError(layout.palette, printer, lut.get(), chromatic);
      std::printf("%s %s: mean CIEDE2000 without LUT %.2f, with %.2f\n", name,
                  chromatic ? "chromatic" : "all six", without, with);
    }
    const double without = MeanPrintError(layout.palette, printer, nullptr, false);
    const double with = MeanPrintError(layout.palette, printer, lut.get(), false);
    if (std::string(name) == "iccv17") {
      // Every colour is within this printer's reach: the LUT can correct it.
      EXPECT_LE(2 * with, without) << name;
    } else {
      // The default palette sits on the sRGB gamut's edge, beyond what a
      // printer that loses 15 % of the chroma can print: the LUT gets as
      // close as the printer allows, which is not twice as close.
      EXPECT_LE(with, without) << name;
    }
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace chromatag

namespace chromatag {
namespace {

// The iccv17 palette printed at 0.8 of its chroma (as SceneTag::print_chroma
// prints it), with no hue turn or dot gain.
SimPrinter FadedIccv17Printer() {
  SimPrinter printer;
  printer.chroma_scale = 0.8;
  printer.hue_shift_deg = 0.0;
  printer.dot_gain = 0.0;
  printer.black_l = 10.0;
  return printer;
}

// Two photos of the sheet under one light (`cast`, R, G, B), at two
// exposures and angles; the brightest channel of the paper at 0.85.
std::vector<PhotoInput> OneLight(const CalibSheetLayout& layout, const SimPrinter& printer,
                                 const cv::Vec3d& cast) {
  SimCamera near, far;
  near.gains = far.gains = cast;
  near.exposure = 0.85 / std::max({cast[0], cast[1], cast[2]});
  far.exposure = 0.75 * near.exposure;
  far.falloff = 0.3;
  far.seed = 2;
  far.page_corners_px = {{{560, 90}, {1180, 60}, {1130, 1140}, {520, 1170}}};
  return {{"near.png", RenderSheetPhoto(layout, printer, near)},
          {"far.png", RenderSheetPhoto(layout, printer, far)}};
}

// All 28 kept 16h5 IDs in iccv17 at 0.8 of its chroma, `size` px, through a
// linear camera under `cast` at `exposure`, with blur and noise.
testing::Scene CastScene(const cv::Vec3d& cast, double exposure, double size) {
  const std::vector<int>& ids = TagFamily::Load("16h5")->kept_ids();
  const double pitch = std::ceil(size * 1.9);
  std::vector<testing::SceneTag> tags;
  for (size_t i = 0; i < ids.size(); ++i) {
    testing::SceneTag tag;
    tag.id = ids[i];
    tag.black_square_px = size;
    tag.centre = {pitch * (0.5 + static_cast<double>(i % 7)) + 0.3,
                  pitch * (0.5 + static_cast<double>(i / 7)) - 0.2};
    tag.rotation_deg = 7 + 13 * (i % 4);
    tag.palette = "iccv17";
    tag.print_chroma = 0.8;
    tags.push_back(tag);
  }
  testing::SceneOptions options;
  options.width = static_cast<int>(pitch * 7);
  options.height = static_cast<int>(pitch * 4);
  options.linear_camera = true;
  options.exposure = exposure;
  options.gain = cast;
  options.blur_sigma = 0.7;
  options.noise_sigma = 1;
  options.shot_noise = 0.02;
  options.seed = 7;
  return testing::RenderScene(tags, options);
}

// The thresholds derived from the colours as shot, with no white balance.
DetectorOptions AsShotThresholds(const CalibrationResult& result) {
  std::vector<Margins> per_photo;
  for (const PhotoResult& photo : result.photos) {
    const auto shades = ReadShades(result.layout, photo.measurement);
    const Margins as_shot = MarginsOf({shades[0], shades[1], shades[2], shades[3]},
                                      shades[static_cast<int>(Shade::kWhite)].seen.L, true);
    per_photo.push_back(Worst(photo.normalised, as_shot));
  }
  return DeriveThresholds(per_photo).options;
}

// Tags of `scene` found with their true ID; a wrong ID fails the test.
int Found(const DetectorOptions& options, const testing::Scene& scene) {
  DetectorOptions o = options;
  o.families = {"16h5"};
  std::string error;
  const auto detector = Detector::Create(o, &error);
  EXPECT_TRUE(detector) << error;
  if (!detector) return 0;
  int found = 0;
  for (const Detection& d : detector->Detect(scene.bgr).detections) {
    bool known = false;
    for (const testing::TagTruth& t : scene.truth) known |= t.id == d.id;
    EXPECT_TRUE(known) << "wrong ID " << d.id;
    found += known ? 1 : 0;
  }
  return found;
}

// A green cast (red and blue at 0.6 of green) turns the faded reds towards
// grey. The calibration measures the cast on the paper and writes gains that
// undo it; with them the detector finds all 28 tags, as the default does in
// neutral light. (So, here, do the default detector and thresholds
// calibrated from the colours as shot, since each tag is judged in the light
// of its own quiet zone; with the gains the stages before a quiet zone is
// found see the paper as neutral too.)
TEST(CalibCalibrateTest, WhiteBalanceUndoesAGreenCastAndFindsEveryTag) {
  const CalibSheetLayout layout = Sheet("iccv17");
  const cv::Vec3d cast(0.6, 1.0, 0.6);
  std::string error;
  const auto result = Calibrate(layout, OneLight(layout, FadedIccv17Printer(), cast), {}, &error);
  ASSERT_TRUE(result) << error;
  const WhiteBalance& wb = result->white_balance;
  std::printf(
      "gains %.3f %.3f %.3f, residual cast %.2f, finding margin %.1f as shot, %.1f "
      "balanced\n",
      wb.gains[0], wb.gains[1], wb.gains[2], wb.worst_residual_cast, wb.finding_margin_as_shot,
      wb.finding_margin_balanced);
  ASSERT_EQ(wb.outcome, WhiteBalanceOutcome::kWritten) << wb.why;
  // The gains undo the cast: 1 / 0.6 for red and blue, over the largest.
  EXPECT_DOUBLE_EQ(wb.gains[0], 1.0);
  EXPECT_NEAR(wb.gains[1], 0.6, 0.6 * 0.02);
  EXPECT_DOUBLE_EQ(wb.gains[2], 1.0);
  EXPECT_LT(wb.worst_residual_cast, 0.5);
  // Without them the paler red reads at the detector's floor for a red.
  EXPECT_LT(wb.finding_margin_as_shot, 2.0);
  EXPECT_GT(wb.finding_margin_balanced, 8.0);
  for (const std::string& w : result->warnings)
    EXPECT_EQ(w.find("white balance"), std::string::npos) << w;

  // The config file carries them.
  const std::string dir = TempDir();
  ASSERT_TRUE(WriteFilesAtomically(CalibrationFiles(*result, dir), &error)) << error;
  DetectorOptions calibrated;
  ASSERT_TRUE(LoadDetectorConfig(dir + "/detector.json", &calibrated, &error)) << error;
  std::filesystem::remove_all(dir);
  EXPECT_EQ(calibrated.white_balance, wb.gains);

  const testing::Scene frame = CastScene(cast, 0.4, 60);
  const int by_default = Found(DetectorOptions{}, frame);
  const int by_thresholds_alone = Found(AsShotThresholds(*result), frame);
  const int by_calibrated = Found(calibrated, frame);
  const int in_neutral_light = Found(DetectorOptions{}, CastScene({1, 1, 1}, 0.4, 60));
  std::printf(
      "of 28 tags under the cast: default %d, thresholds as shot %d, calibrated %d; in "
      "neutral light %d\n",
      by_default, by_thresholds_alone, by_calibrated, in_neutral_light);
  EXPECT_EQ(by_calibrated, 28);
  EXPECT_GE(by_calibrated, by_default);
  EXPECT_GE(by_calibrated, by_thresholds_alone);
  EXPECT_EQ(in_neutral_light, 28);
}

// A tungsten lamp and daylight (the named cameras of the press tests):
// each photo's own gains undo its light, but no one set undoes both, so the
// config holds none and a warning says why.
TEST(CalibCalibrateTest, PhotosUnderDifferentLightsGiveNoWhiteBalance) {
  const CalibSheetLayout layout = Sheet("iccv17");
  const SimPrinter printer = FadedIccv17Printer();
  const cv::Mat page = RasterizeCalibPage(layout, 6.0);
  std::vector<PhotoInput> photos;
  for (const testing::NamedCamera& light : testing::TungstenAndDaylight()) {
    photos.push_back(
        {light.name + ".png",
         testing::PrintAndPhotograph(
             page, 6.0, [&](const Rgb8& sent) { return printer.Print(sent); }, {}, light.camera)});
  }
  std::string error;
  const auto result = Calibrate(layout, photos, {}, &error);
  ASSERT_TRUE(result) << error;
  const WhiteBalance& wb = result->white_balance;
  std::printf("tungsten %.3f %.3f %.3f, daylight %.3f %.3f %.3f; residual cast %.1f\n",
              wb.per_photo[0][0], wb.per_photo[0][1], wb.per_photo[0][2], wb.per_photo[1][0],
              wb.per_photo[1][1], wb.per_photo[1][2], wb.worst_residual_cast);
  EXPECT_EQ(wb.outcome, WhiteBalanceOutcome::kDisagree);
  EXPECT_EQ(wb.gains, (WhiteBalanceGains{1.0, 1.0, 1.0}));
  EXPECT_EQ(result->thresholds.options.white_balance, (std::array<double, 3>{1.0, 1.0, 1.0}));
  // Each photo's own gains undo its light (R 1.25, B 0.7; R 0.95, B 1.08).
  EXPECT_NEAR(wb.per_photo[0][0], 0.7 / 1.25, 0.02);
  EXPECT_NEAR(wb.per_photo[0][1], 0.7, 0.02);
  EXPECT_NEAR(wb.per_photo[1][0], 1.0, 0.02);
  EXPECT_NEAR(wb.per_photo[1][2], 0.95 / 1.08, 0.02);
  EXPECT_GT(wb.worst_residual_cast, 3 * CalibrateOptions{}.white_balance.max_residual_cast);
  int warned = 0;
  for (const std::string& w : result->warnings) {
    if (w.rfind("no white balance: the photos disagree on the light", 0) == 0) ++warned;
  }
  EXPECT_EQ(warned, 1);
  for (const OutputFile& file : CalibrationFiles(*result, "out")) {
    if (file.path != "out/detector.json") continue;
    const size_t options_end = file.contents.find("\"calibration\"");
    EXPECT_EQ(file.contents.substr(0, options_end).find("white_balance"), std::string::npos)
        << file.contents;
  }
  for (const std::string& overlap : ReportOverlaps(*result)) ADD_FAILURE() << overlap;
}

// A warm cast (red 1.6, blue 0.5 of green) makes the reds redder: the
// gains that undo it would darken the picture to its blue channel's level
// and take more a* from the reds than the light does. The calibration
// measures them and leaves them out, and the config finds more tags than
// the same config with them.
TEST(CalibCalibrateTest, AWarmCastNeedsNoWhiteBalance) {
  const CalibSheetLayout layout = Sheet("iccv17");
  const cv::Vec3d cast(1.6, 1.0, 0.5);
  std::string error;
  const auto result = Calibrate(layout, OneLight(layout, FadedIccv17Printer(), cast), {}, &error);
  ASSERT_TRUE(result) << error;
  const WhiteBalance& wb = result->white_balance;
  std::printf("%s\n", wb.why.c_str());
  EXPECT_EQ(wb.outcome, WhiteBalanceOutcome::kNotNeeded);
  EXPECT_NEAR(wb.shared[0], 0.5 / 1.6, 0.02);
  EXPECT_NEAR(wb.shared[1], 0.5, 0.02);
  EXPECT_GT(wb.finding_margin_as_shot, wb.finding_margin_balanced + 5);
  EXPECT_EQ(result->thresholds.options.white_balance, (std::array<double, 3>{1.0, 1.0, 1.0}));
  for (const std::string& w : result->warnings)
    EXPECT_EQ(w.find("white balance"), std::string::npos) << w;
  DetectorOptions with_gains = result->thresholds.options;
  with_gains.white_balance = wb.shared;
  int as_written = 0, balanced = 0;
  for (double size : {30.0, 45.0}) {
    const testing::Scene frame = CastScene(cast, 0.4, size);
    as_written += Found(result->thresholds.options, frame);
    balanced += Found(with_gains, frame);
  }
  std::printf("of 56 tags: as written %d, with the gains %d\n", as_written, balanced);
  EXPECT_GT(as_written, balanced);
}

}  // namespace
}  // namespace chromatag
