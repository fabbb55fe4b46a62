#include "chromatag/verify/sheet_check.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "chromatag/base/output_files.h"
#include "chromatag/base/sha256.h"

namespace chromatag {
namespace {

std::string Fixed(double value, int decimals) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::string Describe(const SheetRecord& record, const PlacedTag& tag) {
  return record.family->name() + " ID " + std::to_string(tag.id) + " (page " +
         std::to_string(tag.page + 1) + ", centre " + Fixed(tag.center_mm[0], 1) + ", " +
         Fixed(tag.center_mm[1], 1) + " mm)";
}

double Distance(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// Fills in a tag's verdict from its counts and first match.
void Judge(const SheetRecord& record, const VerifyOptions& options, TagVerdict* v) {
  const std::string who = Describe(record, v->expected);
  if (v->times_found == 0) {
    v->problem = who + ": not found";
  } else if (v->times_found > 1) {
    v->problem = who + ": found " + std::to_string(v->times_found) + " times";
  } else if (v->found_id != v->expected.id) {
    v->problem = who + ": decodes as ID " + std::to_string(v->found_id) +
                 " where the sidecar says ID " + std::to_string(v->expected.id);
  } else if (v->hamming != 0) {
    v->problem = who + ": decodes only with " + std::to_string(v->hamming) +
                 " bit(s) corrected, so some cell has the wrong shade";
  } else if (v->position_error_mm > options.max_position_error_mm) {
    v->problem = who + ": found " + Fixed(v->position_error_mm, 2) +
                 " mm from where the sidecar says (tolerance " +
                 Fixed(options.max_position_error_mm, 2) + " mm)";
  }
  v->passed = v->problem.empty();
}

}  // namespace

bool VerifyOptions::IsValid(std::string* error) const {
  if (!(dpi >= 50.0 && dpi <= 1200.0)) {
    if (error) *error = "the resolution must be in [50, 1200] dpi";
    return false;
  }
  if (!(max_position_error_mm > 0.0)) {
    if (error) *error = "the position tolerance must be greater than zero";
    return false;
  }
  return true;
}

std::optional<SheetVerdict> CheckSheet(const SheetRecord& record, const SheetPages& pages,
                                       const Detector& detector, const VerifyOptions& options,
                                       std::string* error) {
  SheetVerdict verdict;
  for (const PlacedTag& tag : record.tags) {
    TagVerdict v;
    v.expected = tag;
    verdict.tags.push_back(v);
  }
  const double reach_mm = record.tag_size_mm / 2.0;  // A detection this close belongs to a tag.
  for (int page = 0; page < pages.size(); ++page) {
    DetectionResult result;
    {
      // Held only while it is searched: one page in memory at a time.
      const cv::Mat image = pages.Render(page, error);
      if (image.empty()) return std::nullopt;
      detector.Detect(image, PixelOrder::kBgr, &result);
    }
    for (const Detection& detection : result.detections) {
      std::array<std::array<double, 2>, 4> corners;
      std::array<double, 2> center{0.0, 0.0};
      for (int i = 0; i < 4; ++i) {
        corners[i] = PixelToMm(detection.corners[i], pages.px_per_mm());
        center[0] += corners[i][0] / 4.0;
        center[1] += corners[i][1] / 4.0;
      }
      TagVerdict* owner = nullptr;
      for (TagVerdict& v : verdict.tags) {
        if (v.expected.page == page && Distance(v.expected.center_mm, center) < reach_mm &&
            (owner == nullptr || Distance(v.expected.center_mm, center) <
                                     Distance(owner->expected.center_mm, center))) {
          owner = &v;
        }
      }
      if (owner == nullptr || detection.family != record.family.get()) {
        verdict.unexpected.push_back({page, detection.family->name(), detection.id, center});
        continue;
      }
      if (++owner->times_found > 1) continue;
      owner->found_id = detection.id;
      owner->hamming = detection.hamming;
      owner->margin = detection.decision_margin;
      for (int i = 0; i < 4; ++i) {
        owner->position_error_mm =
            std::max(owner->position_error_mm, Distance(corners[i], owner->expected.corners_mm[i]));
      }
    }
  }
  for (TagVerdict& v : verdict.tags) {
    Judge(record, options, &v);
    verdict.tags_passed += v.passed ? 1 : 0;
  }
  verdict.passed =
      verdict.tags_passed == static_cast<int>(verdict.tags.size()) && verdict.unexpected.empty();
  return verdict;
}

std::optional<SheetRecord> ReadSheetSidecar(const std::string& sheet_path, std::string* error) {
  if (!std::filesystem::is_regular_file(sheet_path)) {
    if (error) *error = "cannot read sheet '" + sheet_path + "': no such file";
    return std::nullopt;
  }
  auto record = ReadSidecar(SidecarPath(sheet_path), error);
  if (!record) return std::nullopt;
  // The sidecar must describe the file given (and the checks run on the
  // files it names): a sidecar copied or renamed next to another sheet
  // would otherwise vouch for it.
  bool names_sheet = false;
  std::error_code ignored;
  for (const auto& file : record->files)
    names_sheet |= std::filesystem::equivalent(file.path, sheet_path, ignored);
  if (!names_sheet) {
    if (error) {
      *error = "sidecar '" + record->sidecar_path + "' does not describe '" + sheet_path +
               "' (it lists " +
               (record->files.empty() ? "no file" : "'" + record->files[0].path + "'") +
               "); regenerate the sheet to get its own sidecar";
    }
    return std::nullopt;
  }
  return record;
}

std::optional<SheetVerdict> VerifySheetFile(const std::string& sheet_path,
                                            const VerifyOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  auto record = ReadSheetSidecar(sheet_path, error);
  if (!record) return std::nullopt;
  auto pages = SheetPages::Open(*record, options.dpi, error);
  if (!pages) return std::nullopt;
  DetectorOptions detector_options;
  detector_options.families = TagFamily::Names();
  auto detector = Detector::Create(detector_options, error);
  if (!detector) return std::nullopt;
  auto checked = CheckSheet(*record, *pages, *detector, options, error);
  if (!checked) return std::nullopt;
  SheetVerdict& verdict = *checked;
  for (const auto& file : record->files) {
    if (Sha256Hex(ReadFile(file.path)) != file.sha256) {
      verdict.file_problems.push_back("'" + file.path +
                                      "' was changed after it was generated: its SHA-256 "
                                      "differs from the sidecar's");
    }
  }
  verdict.passed = verdict.passed && verdict.file_problems.empty();
  return verdict;
}

}  // namespace chromatag
