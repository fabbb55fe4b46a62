#include "chromatag/generator/sheet_request.h"

#include "chromatag/families/input_file.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/id_list.h"

namespace chromatag {

bool ToSheetOptions(const SheetRequest& in, const std::string& output_path, SheetOptions* out,
                    std::string* error) {
  if (!IsValidUtf8(output_path)) {
    *error = "the output name must be UTF-8 (the sidecar records it)";
    return false;
  }
  out->family = TagFamily::Load(in.family, error);
  if (!out->family) return false;
  if (in.all == !in.ids.empty()) {
    *error = "say which tags: --ids 0-9,12 or --all (not both)";
    return false;
  }
  if (in.all) {
    out->ids = out->family->kept_ids();
  } else {
    auto ids = ParseIdList(in.ids, *out->family, error);
    if (!ids) return false;
    out->ids = *ids;
  }
  const auto size = ParseLength(in.size, error);
  if (!size) return false;
  const auto margin = ParseLength(in.margin == "0" ? "0.000001mm" : in.margin, error);
  if (!margin) return false;
  const auto gap = ParseLength(in.gap == "0" ? "0.000001mm" : in.gap, error);
  if (!gap) return false;
  out->tag_size_mm = size->mm;
  out->margin_mm = margin->mm;
  out->gap_mm = gap->mm;
  const auto page = ParsePageSize(in.page, error);
  if (!page) return false;
  out->page = *page;
  const auto palette = in.palette_file.empty() ? BuiltinPalette(in.palette, error)
                                               : LoadPaletteFile(in.palette_file, error);
  if (!palette) return false;
  out->palette = *palette;
  if (!in.color_lut.empty()) {
    out->color_lut = ColorLut::Load(in.color_lut, error);
    if (!out->color_lut) return false;
  }
  out->tag.quiet_zone_cells = in.quiet_zone;
  out->tag.cut_ring = in.cut_ring;
  out->crop_marks = in.crop_marks;
  out->label = in.label;
  out->one_per_page = in.one_per_page;
  out->dpi = in.dpi;
  std::string extension_error;
  const auto from_extension = FormatFromPath(output_path, &extension_error);
  if (in.format.empty()) {
    if (!from_extension) {
      *error = extension_error;
      return false;
    }
    out->format = *from_extension;
  } else {
    if (in.format == "pdf") {
      out->format = SheetFormat::kPdf;
    } else if (in.format == "svg") {
      out->format = SheetFormat::kSvg;
    } else if (in.format == "png") {
      out->format = SheetFormat::kPng;
    } else {
      *error = "unknown format '" + in.format + "' (allowed: pdf, svg, png)";
      return false;
    }
    // A PNG named x.pdf opens in no PDF viewer and fools whoever trusts the name.
    if (from_extension && *from_extension != out->format) {
      *error = std::string("the format is ") + SheetFormatName(out->format) + " but '" +
               output_path + "' names a " + SheetFormatName(*from_extension) +
               " file: give the output a ." + SheetFormatName(out->format) +
               " name or leave the format out";
      return false;
    }
  }
  return out->IsValid(error);
}

}  // namespace chromatag
