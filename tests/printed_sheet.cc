#include "printed_sheet.h"

#include <unistd.h>

#include <filesystem>

#include "chromatag/generator/sheet.h"

namespace chromatag::testing {

namespace fs = std::filesystem;

PrintedSheet::~PrintedSheet() {
  std::error_code ignored;
  fs::remove_all(dir, ignored);
}

std::unique_ptr<PrintedSheet> MakePrintedSheet(const std::string& name, std::string* error) {
  auto sheet = std::make_unique<PrintedSheet>();
  sheet->dir = fs::temp_directory_path() / (name + "-" + std::to_string(getpid()));
  fs::create_directories(sheet->dir);
  SheetOptions options;
  options.family = TagFamily::Load("16h5");
  options.ids = options.family->kept_ids();
  options.palette = *BuiltinPalette("default");
  options.tag_size_mm = 30.0;
  const std::string path = sheet->dir + "/tags.pdf";
  if (!WriteSheet(options, path, error)) return nullptr;
  auto record = ReadSidecar(SidecarPath(path), error);
  if (!record) return nullptr;
  sheet->record = *record;
  auto images = RasterizeSheet(sheet->record, kPrintedSheetDpi, error);
  if (!images) return nullptr;
  sheet->images = *images;
  sheet->press = IccPress::Load(IccPress::DefaultCmykProfilePath(), error);
  if (!sheet->press) return nullptr;
  return sheet;
}

}  // namespace chromatag::testing
