// The sheet sidecar reader on hostile JSON and, when a sidecar parses, what
// `verify --print` does with its numbers, without its files: one fixed scan
// (fuzz_sheets.h's PrintSheet page, whose sidecars are the seeds, so that
// mutated ones still pair with the tags it shows) is checked against the
// record as CheckPrintFiles checks an image (as a flatbed scan, a photo, or
// a photo through a lens with distortion: the input's length chooses), and
// the verdict is written as JSON and drawn as the PDF report. The record's
// tag corners, page and tag size then drive the page fit, the tag
// predictions, the page view and the report's drawing.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/print_check.h"
#include "fuzz_sheets.h"

namespace {

constexpr char kFolder[] = "/nonexistent-fuzz/";

// Larger records are refused before any check: the reader caps pages at
// 100000 and tags only by the input's length.
constexpr int kMaxPages = 2000;
constexpr size_t kMaxTags = 2000;
// CheckPrintImage resamples the image onto the page at 3 px/mm (fewer past
// 1.3 m): 16 Mpx for a page of 1.3 m a side, seconds a run. A4 is 0.56 Mpx.
constexpr double kMaxViewPixels = 2e6;

struct Fixture {
  cv::Mat scan;
  std::unique_ptr<chromatag::Detector> detector;
};

const Fixture& GetFixture() {
  static const Fixture* fixture = [] {
    auto* f = new Fixture;
    std::string error;
    const auto files = chromatag::RenderSheet(chromatag::fuzz::PrintSheet(), "sheet.png", &error);
    if (files) f->scan = chromatag::DecodeImage(files->front().contents, "scan", &error);
    // As CheckPrintFiles makes it: both families, rejected candidates kept.
    chromatag::DetectorOptions options;
    options.families = chromatag::TagFamily::Names();
    options.report_rejected = true;
    f->detector = chromatag::Detector::Create(options, &error);
    if (f->scan.empty() || !f->detector) {
      std::fprintf(stderr, "fuzz_print_sidecar: no fixture: %s\n", error.c_str());
      std::abort();
    }
    return f;
  }();
  return *fixture;
}

void Check(bool ok, const char* promise) {
  if (ok) return;
  std::fprintf(stderr, "broken promise: %s\n", promise);
  std::abort();
}

// What ParseSidecar's header promises of a record it returns.
void CheckRecord(const chromatag::SheetRecord& record) {
  Check(record.family != nullptr, "a known family");
  Check(record.num_pages >= 1, "at least one page");
  const size_t files = record.format == chromatag::SheetFormat::kPdf ? 1 : record.num_pages;
  Check(record.files.size() == files, "one PDF or one file a page");
  for (const auto& file : record.files) {
    const std::string name = file.path.substr(sizeof(kFolder) - 1);
    Check(file.path.rfind(kFolder, 0) == 0 && !name.empty() && name.find('/') == std::string::npos,
          "files beside the sidecar");
  }
  for (const auto& tag : record.tags) {
    Check(record.family->IsValidId(tag.id), "kept IDs");
    Check(tag.page >= 0 && tag.page < record.num_pages, "pages in range");
  }
}

double ViewPixels(const chromatag::PageSize& page) {
  const double side = std::max(page.width_mm, page.height_mm);
  if (!(side > 0 && side <= chromatag::kMaxPageSideMm)) return 0;  // Refused at once.
  const double s = std::min(3.0, 4000.0 / side);
  return page.width_mm * s * page.height_mm * s;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const Fixture& fixture = GetFixture();
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto record = chromatag::ParseSidecar(text, kFolder, &error);
  if (!record) {
    Check(!error.empty(), "a refusal says why");
    return 0;
  }
  CheckRecord(*record);
  if (record->num_pages > kMaxPages || record->tags.size() > kMaxTags ||
      ViewPixels(record->page) > kMaxViewPixels)
    return 0;

  chromatag::PrintCheckOptions options;
  chromatag::PrintImage image;
  image.name = "scan.png";
  switch (size % 3) {
    case 0:
      options.scans = true;
      image.dpi_x = image.dpi_y = chromatag::fuzz::kScanDpi;
      break;
    case 1:
      break;
    case 2:
      options.camera = chromatag::CameraIntrinsics{280, 280, 138, 138, {0.08, -0.03, 0.001, 0}};
      break;
  }
  Check(options.IsValid(&error), "the harness's options are valid");
  chromatag::PrintVerdict verdict;
  verdict.images.push_back(
      chromatag::CheckPrintImage(*record, fixture.scan, image, *fixture.detector, options));
  const chromatag::PrintPageResult& page = verdict.images.back();
  Check(page.problems.size() == page.problem_grades.size(), "a grade for each page problem");
  Check(page.page < record->num_pages, "a page of the sheet, or none");
  if (!page.tags.empty()) {  // None when the found tags do not fit the layout.
    const auto on_page = std::count_if(record->tags.begin(), record->tags.end(),
                                       [&](const auto& t) { return t.page == page.page; });
    Check(page.tags.size() == static_cast<size_t>(on_page), "every tag of the page checked");
  }
  for (const auto& tag : page.tags) {
    Check(tag.problems.size() == tag.problem_grades.size(), "a grade for each tag problem");
    verdict.grade = std::max(verdict.grade, tag.grade);
  }
  verdict.grade = std::max(verdict.grade, page.grade);
  const std::string json = chromatag::PrintVerdictJson(*record, verdict);
  Check(!nlohmann::json::parse(json, nullptr, false).is_discarded(), "the verdict is JSON");
  Check(!chromatag::RenderPrintReportPdf(*record, verdict).empty(), "a PDF report");
  return 0;
}
