// The record of a rendered sheet that its sidecar holds (the format is the
// layout library's: chromatag/layout/sheet_record.h).
#include "chromatag/base/sha256.h"
#include "sheet_internal.h"

namespace chromatag::internal {
namespace {

std::string BaseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

}  // namespace

SheetRecord SheetRecordOf(const SheetOptions& options, const SheetLayout& layout,
                          const std::vector<OutputFile>& page_files) {
  SheetRecord record;
  record.family = options.family;
  record.tag_size_mm = options.tag_size_mm;
  record.quiet_zone_cells = options.tag.quiet_zone_cells;
  record.palette = options.palette;
  record.page = options.page;
  record.num_pages = layout.num_pages;
  record.format = options.format;
  record.dpi = options.dpi;
  record.margin_mm = options.margin_mm;
  record.cut_ring = options.tag.cut_ring;
  record.crop_marks = options.crop_marks;
  record.label = options.label && !options.board;
  const TagColors written = SheetColors(options);
  for (Shade shade : kAllShades)
    record.written_rgb[static_cast<int>(shade)] = ToRgb8(written[shade]);
  if (options.color_lut) record.color_lut = BaseName(options.color_lut->path());
  for (const auto& file : page_files) {
    record.files.push_back({BaseName(file.path), Sha256Hex(file.contents)});
  }
  record.tags = layout.tags;
  record.board = options.board;
  record.board_origin_mm = layout.board_origin_mm;
  return record;
}

}  // namespace chromatag::internal
