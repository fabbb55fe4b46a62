// Rasterising a sheet file as `verify` does (SheetPages: poppler for a PDF,
// librsvg for an SVG) on arbitrary bytes: an input starting with '<' is read
// as an SVG, any other as a PDF, as a one-page sheet at a low resolution so
// that a run takes milliseconds. Both renderers read files only, so the
// bytes go to a file of this process's own in /tmp, removed after each run.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include <opencv2/core.hpp>

#include "chromatag/families/family.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/raster.h"

namespace {

// 36 dpi: half a point a pixel, an A4 page 298 x 421 px.
constexpr double kDpi = 36.0;

void Check(bool ok, const char* promise) {
  if (ok) return;
  std::fprintf(stderr, "broken promise: %s\n", promise);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool svg = size > 0 && data[0] == '<';
  const std::string path =
      "/tmp/chromatag-fuzz-raster-" + std::to_string(getpid()) + (svg ? ".svg" : ".pdf");
  {
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  chromatag::SheetRecord record;
  record.family = chromatag::TagFamily::Load("16h5");
  record.format = svg ? chromatag::SheetFormat::kSvg : chromatag::SheetFormat::kPdf;
  record.num_pages = 1;
  record.files.push_back({path, ""});
  std::string error;
  const auto pages = chromatag::SheetPages::Open(record, kDpi, &error);
  if (!pages) {
    Check(!error.empty(), "a refusal says why");
  } else {
    Check(pages->size() == record.num_pages, "the sidecar's page count");
    for (int i = 0; i < pages->size(); ++i) {
      error.clear();
      const cv::Mat page = pages->Render(i, &error);
      Check(page.empty() ? !error.empty() : page.type() == CV_8UC3,
            "BGR pixels, or an empty Mat and why");
    }
  }
  std::remove(path.c_str());  // Nothing left in /tmp when the run ends.
  return 0;
}
