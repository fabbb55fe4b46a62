// The calibration run and its output files (calibrate.h).
#include "chromatag/calib/calibrate.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "chromatag/calib/cube_lut.h"
#include "chromatag/calib/report.h"
#include "chromatag/detector/config.h"
#include "chromatag/detector/detector.h"
#include "chromatag/families/version.h"
#include "chromatag/rig/board_file.h"

namespace chromatag {
namespace {

using Json = nlohmann::ordered_json;

// Above this mean residual the model does not describe the photo well
// (CIEDE2000): the LUT built from it is suspect.
constexpr double kPoorFitMeanDeltaE = 3.0;

double Round2(double v) { return std::round(v * 100.0) / 100.0; }
Json LabJson(const Lab& lab) { return {Round2(lab.L), Round2(lab.a), Round2(lab.b)}; }

std::vector<PrinterSample> Samples(const CalibSheetLayout& layout, const PhotoMeasurement& m,
                                   std::vector<int>* patches) {
  std::vector<PrinterSample> samples;
  for (const Patch& patch : layout.patches) {
    const PatchMeasurement& pm = m.patches[patch.index];
    if (!pm.usable()) continue;
    const Rgb sent = patch.kind == PatchKind::kPaper ? Rgb{1, 1, 1} : ToRgb(patch.rgb);
    samples.push_back({sent, pm.lab, patch.index});
    patches->push_back(patch.index);
  }
  return samples;
}

Json MarginsJson(const Margins& m) {
  return {{"a_gap", Round2(m.a_gap)},
          {"red_b_gap", Round2(m.red_b_gap)},
          {"green_b_gap", Round2(m.green_b_gap)},
          {"a_spread", Round2(m.a_spread)},
          {"min_red_a", Round2(m.min_red_a)},
          {"max_green_a", Round2(m.max_green_a)},
          {"noise_a", Round2(m.noise_a)},
          {"l_gap_white", Round2(m.l_gap_white)},
          {"expected_decision_margin", Round2(m.decision())}};
}

Json GainsJson(const WhiteBalanceGains& g) { return {g[0], g[1], g[2]}; }

// The white balance's provenance: written or not and why, the gains the
// photos share and the cast each photo's paper keeps through them.
Json WhiteBalanceJson(const WhiteBalance& wb) {
  Json out = {{"written", wb.written()},
              {"shared_gains", GainsJson(wb.shared)},
              {"worst_residual_cast", Round2(wb.worst_residual_cast)},
              {"finding_margin_as_shot", Round2(wb.finding_margin_as_shot)},
              {"finding_margin_balanced", Round2(wb.finding_margin_balanced)}};
  if (!wb.written()) out["why_not"] = wb.why;
  return out;
}

std::string Provenance(const CalibrationResult& r) {
  Json photos = Json::array();
  for (const PhotoResult& p : r.photos) photos.push_back(p.name);
  Json verdicts = Json::array();
  for (const PairVerdict& v : r.thresholds.verdicts) {
    verdicts.push_back({{"pair", v.pair}, {"verdict", VerdictName(v.verdict)}, {"why", v.why}});
  }
  const Json root = {{"tool", std::string("chromatag calibrate ") + kVersion},
                     {"sheet_id", r.layout.sheet_id},
                     {"palette", r.layout.palette.name},
                     {"photos", photos},
                     {"safety_factor", r.options.thresholds.safety_factor},
                     {"white_balance", WhiteBalanceJson(r.white_balance)},
                     {"worst_margins", MarginsJson(r.thresholds.worst)},
                     {"verdicts", verdicts},
                     {"warnings", r.warnings}};
  return root.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string MeasurementsJson(const CalibrationResult& r) {
  Json photos = Json::array();
  for (size_t photo = 0; photo < r.photos.size(); ++photo) {
    const PhotoResult& p = r.photos[photo];
    std::vector<double> residual(r.layout.patches.size(), -1.0);
    for (size_t i = 0; i < p.fit_patches.size(); ++i)
      residual[p.fit_patches[i]] = p.fit.residual_de[i];
    Json patches = Json::array();
    for (const Patch& patch : r.layout.patches) {
      const PatchMeasurement& m = p.measurement.patches[patch.index];
      Json item = {{"index", patch.index},
                   {"kind", PatchKindName(patch.kind)},
                   {"intended", LabJson(patch.lab)},
                   {"flags", FlagNames(m.flags)},
                   {"pixels", m.pixels},
                   {"as_shot", LabJson(m.as_shot)},
                   {"seen", LabJson(SeenThrough(m.camera_rgb, r.white_balance.gains))},
                   {"lab", LabJson(m.lab)}};
      const Rgb sent = patch.kind == PatchKind::kPaper ? Rgb{1, 1, 1} : ToRgb(patch.rgb);
      item["model"] = LabJson(p.fit.model.Predict(sent));
      item["model_de2000"] =
          residual[patch.index] < 0 ? Json(nullptr) : Json(Round2(residual[patch.index]));
      patches.push_back(item);
    }
    photos.push_back({{"name", p.name},
                      {"px_per_mm", Round2(p.measurement.location.px_per_mm)},
                      {"white_level", Round2(p.measurement.white_level)},
                      {"flagged", p.measurement.flagged},
                      {"white_balance", GainsJson(r.white_balance.per_photo[photo])},
                      {"paper_residual_cast", LabJson(r.white_balance.residual[photo])},
                      {"fit_mean_de2000", Round2(p.fit.mean_de)},
                      {"fit_max_de2000", Round2(p.fit.max_de)},
                      {"margins_normalised", MarginsJson(p.normalised)},
                      {"margins_seen", MarginsJson(p.seen)},
                      {"patches", patches}});
  }
  const Json root = {{"schema", "chromatag-calib-measurements"},
                     {"schema_version", 1},
                     {"sheet_id", r.layout.sheet_id},
                     {"photos", photos}};
  return root.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string Join(const std::string& folder, const char* name) {
  if (folder.empty()) return name;
  return folder.back() == '/' ? folder + name : folder + "/" + name;
}

// Measures one photo and fits the printer to it; nullopt and "NAME: why" when
// the photo cannot be used.
std::optional<PhotoResult> MeasureAndFit(const CalibSheetLayout& layout, const PhotoInput& input,
                                         const CalibrateOptions& options, std::string* error) {
  std::string why;
  PhotoResult photo;
  photo.name = input.name;
  const auto m = MeasurePhoto(input.bgr, layout, options.measure, options.locate, &why);
  if (!m) {
    if (error) *error = input.name + ": " + why;
    return std::nullopt;
  }
  photo.measurement = *m;
  const auto fit = FitPrinterModel(Samples(layout, *m, &photo.fit_patches), options.model, &why);
  if (!fit) {
    if (error) *error = input.name + ": " + why;
    return std::nullopt;
  }
  photo.fit = *fit;
  return photo;
}

// The photo's shades and margins, normalised and as a detector with
// `white_balance` sees them; returns the worse of the two.
Margins ReadMargins(const CalibSheetLayout& layout, const WhiteBalanceGains& white_balance,
                    PhotoResult* photo) {
  photo->shades = ReadShades(layout, photo->measurement, white_balance);
  const std::array<ShadeReading, 4> chromatic = {photo->shades[0], photo->shades[1],
                                                 photo->shades[2], photo->shades[3]};
  const ShadeReading& white = photo->shades[static_cast<int>(Shade::kWhite)];
  photo->normalised = MarginsOf(chromatic, white.lab.L, false);
  photo->seen = MarginsOf(chromatic, white.seen.L, true);
  return Worst(photo->normalised, photo->seen);
}

}  // namespace

bool CalibrateOptions::IsValid(std::string* error) const {
  if (!locate.IsValid(error) || !measure.IsValid(error) || !model.IsValid(error) ||
      !white_balance.IsValid(error) || !thresholds.IsValid(error) || !palette.IsValid(error))
    return false;
  if (lut_size < 2 || lut_size > 65) {
    if (error) *error = "LUT size must be in [2, 65]";
    return false;
  }
  return true;
}

std::optional<CalibrationResult> Calibrate(const CalibSheetLayout& layout,
                                           const std::vector<PhotoInput>& photos,
                                           const CalibrateOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  if (photos.empty()) {
    if (error) *error = "no photo given";
    return std::nullopt;
  }
  CalibrationResult result;
  result.layout = layout;
  result.options = options;
  std::vector<PhotoMeasurement> measurements;
  std::vector<PrinterModel> models;
  std::vector<std::string> names;
  for (const PhotoInput& input : photos) {
    auto photo = MeasureAndFit(layout, input, options, error);
    if (!photo) return std::nullopt;
    if (photo->fit.mean_de > kPoorFitMeanDeltaE) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "%s: the printer model fits poorly (mean CIEDE2000 %.1f): uneven light or "
                    "glare? The LUT is less reliable",
                    input.name.c_str(), photo->fit.mean_de);
      result.warnings.push_back(text);
    }
    measurements.push_back(photo->measurement);
    models.push_back(photo->fit.model);
    names.push_back(input.name);
    result.photos.push_back(std::move(*photo));
  }
  // The thresholds are for the detector as the config sets it up: its
  // white balance first, then the margins as it sees them.
  result.white_balance = MeasureWhiteBalance(layout, measurements, names, options.white_balance);
  // Photos that disagree, or a cast too strong, are a problem with the
  // photos or the light; a white balance not needed is not.
  const WhiteBalanceOutcome outcome = result.white_balance.outcome;
  if (outcome == WhiteBalanceOutcome::kDisagree || outcome == WhiteBalanceOutcome::kTooStrong)
    result.warnings.push_back("no white balance: " + result.white_balance.why);
  std::vector<Margins> worst_per_photo;
  for (PhotoResult& photo : result.photos)
    worst_per_photo.push_back(ReadMargins(layout, result.white_balance.gains, &photo));
  result.thresholds = DeriveThresholds(worst_per_photo, options.thresholds);
  result.thresholds.options.white_balance = result.white_balance.gains;
  result.warnings.insert(result.warnings.end(), result.thresholds.warnings.begin(),
                         result.thresholds.warnings.end());
  result.palette = ChoosePalette(layout, measurements, options.palette, &result.palette_error);
  if (!result.palette) result.warnings.push_back("no palette written: " + result.palette_error);
  const auto cube = BakeCubeLut(models, options.lut_size, error);
  if (!cube) return std::nullopt;
  result.cube = *cube;
  return result;
}

std::vector<OutputFile> CalibrationFiles(const CalibrationResult& result,
                                         const std::string& folder) {
  std::vector<OutputFile> files;
  std::vector<std::string> fields = {"adiff_thresh", "border_thresh", "min_decision_margin",
                                     "max_green_a", "two_step_rises"};
  if (result.white_balance.written()) fields.push_back("white_balance");
  files.push_back({Join(folder, kDetectorConfigFile),
                   DetectorConfigToJson(result.thresholds.options, fields, Provenance(result))});
  if (result.palette)
    files.push_back({Join(folder, kPaletteFile), PaletteToJson(result.palette->palette)});
  files.push_back({Join(folder, kLutFile), result.cube});
  files.push_back({Join(folder, kReportPdfFile), RenderReportPdf(result)});
  files.push_back({Join(folder, kReportPngFile), RenderReportPng(result)});
  files.push_back({Join(folder, kMeasurementsFile), MeasurementsJson(result)});
  return files;
}

std::optional<CameraCalibration> CalibrateCameraFromPhotos(const CalibSheetLayout& layout,
                                                           const std::vector<PhotoInput>& photos,
                                                           std::string* why) {
  const auto fail = [&](const std::string& message) -> std::optional<CameraCalibration> {
    if (why) *why = message;
    return std::nullopt;
  };
  if (photos.size() < 3) {
    return fail(std::to_string(photos.size()) +
                " photo(s); the camera needs 3 or more (better 10-20), the sheet tilted "
                "differently in each");
  }
  for (const PhotoInput& photo : photos) {
    if (photo.bgr.size() != photos.front().bgr.size())
      return fail("the photos are not all one size ('" + photo.name + "' differs from '" +
                  photos.front().name + "')");
  }
  const auto board = BoardFromCalibSheet(layout, why);
  if (!board) return std::nullopt;
  DetectorOptions options;
  options.families = {layout.family};
  const auto detector = Detector::Create(options, why);
  if (!detector) return std::nullopt;
  std::vector<CalibrationView> views;
  DetectionResult result;
  for (const PhotoInput& photo : photos) {
    detector->Detect(photo.bgr, PixelOrder::kBgr, &result);
    views.push_back({photo.name, result.detections});
  }
  auto camera = CalibrateCamera(*board, views, photos.front().bgr.size(), {}, why);
  if (!camera) return std::nullopt;
  // Photos taken square-on to the sheet, as for colour alone, fit any focal
  // length: no camera file rather than a wrong one.
  int tilted = 0;
  for (const CalibrationViewResult& v : camera->views) tilted += v.used && v.tilt_deg >= 20 ? 1 : 0;
  if (tilted < 3) {
    return fail(std::to_string(tilted) +
                " photo(s) show the sheet tilted 20 degrees or more; the focal length needs 3 or "
                "more, tilted 20-45 degrees about different axes");
  }
  if (!camera->doubts.empty()) return fail(camera->doubts.front());
  return camera;
}

}  // namespace chromatag
