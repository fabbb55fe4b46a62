#include <iostream>

#include "chromatag/families/palette.h"
#include "chromatag/generator/id_list.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/units.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

struct GenerateOptions {
  std::string family = "16h5";
  std::string ids;
  bool all = false;
  std::string size = "40mm";
  std::string page = "a4";
  std::string margin = "10mm";
  std::string gap = "5mm";
  int quiet_zone = 2;
  bool cut_ring = false;
  bool crop_marks = false;
  bool no_label = false;
  bool one_per_page = false;
  std::string palette = "default";
  std::string palette_file;
  std::string color_lut;
  std::string format;  // Empty: from the output's extension.
  double dpi = 300.0;
  std::string output;
};

int Fail(const std::string& message) {
  std::cerr << "chromatag generate: " << message << "\n";
  return kExitUsage;
}

// Turns the command line into SheetOptions; false with *error on bad input.
bool ToSheetOptions(const GenerateOptions& in, SheetOptions* out, std::string* error) {
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
  const auto margin = ParseLength(in.margin == "0" ? "0.000001mm" : in.margin, error);
  const auto gap = ParseLength(in.gap == "0" ? "0.000001mm" : in.gap, error);
  if (!size || !margin || !gap) return false;
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
  out->label = !in.no_label;
  out->one_per_page = in.one_per_page;
  out->dpi = in.dpi;
  if (in.format.empty()) {
    const auto format = FormatFromPath(in.output, error);
    if (!format) return false;
    out->format = *format;
  } else {
    out->format = in.format == "pdf"   ? SheetFormat::kPdf
                  : in.format == "svg" ? SheetFormat::kSvg
                                       : SheetFormat::kPng;
  }
  return out->IsValid(error);
}

int RunGenerate(const GenerateOptions& options) {
  SheetOptions sheet;
  std::string error;
  if (!ToSheetOptions(options, &sheet, &error)) return Fail(error);
  const auto layout = LayoutSheet(sheet, &error);
  if (!layout) return Fail(error);
  std::vector<std::string> written;
  if (!WriteSheet(sheet, options.output, &error, &written)) return Fail(error);
  std::cout << "Wrote " << sheet.ids.size() << " " << sheet.family->name() << " tag"
            << (sheet.ids.size() == 1 ? "" : "s") << " of " << sheet.tag_size_mm << " mm on "
            << layout->num_pages << " " << sheet.page.name << " page"
            << (layout->num_pages == 1 ? "" : "s") << " (" << layout->columns << " x "
            << layout->rows << " per page), palette " << sheet.palette.name
            << (sheet.color_lut ? " through " + sheet.color_lut->path() : "") << ":\n";
  for (const auto& path : written) std::cout << "  " << path << "\n";
  return kExitOk;
}

}  // namespace

void RegisterGenerate(CLI::App& app, Action* action) {
  auto o = std::make_shared<GenerateOptions>();
  CLI::App* c = app.add_subcommand(
      "generate", "Write print-ready tags at exact physical size (PDF, SVG or PNG) with a sidecar");
  c->add_option("--family", o->family, "Tag family")
      ->capture_default_str()
      ->check(CLI::IsMember(TagFamily::Names()));
  auto* ids = c->add_option("--ids", o->ids, "Tag IDs, e.g. 0-9,12,20-27");
  c->add_flag("--all", o->all, "Every kept ID of the family")->excludes(ids);
  c->add_option("--size", o->size, "Tag size: side of the black square (mm, cm, m, in)")
      ->capture_default_str();
  c->add_option("--page", o->page, "a4, a3, letter, legal, or WxH with a unit (210x297mm)")
      ->capture_default_str();
  c->add_option("--margin", o->margin, "Blank border on every side of the page")
      ->capture_default_str();
  c->add_option("--gap", o->gap, "Space between tags")->capture_default_str();
  c->add_option("--quiet-zone", o->quiet_zone, "White ring around the black square, in cells")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
  c->add_flag("--cut-ring", o->cut_ring, "A light grey ring to cut along");
  c->add_flag("--crop-marks", o->crop_marks, "Crop marks at the corners of each tag");
  c->add_flag("--no-label", o->no_label, "No 'family ID size' line under the tags");
  c->add_flag("--one-per-page", o->one_per_page, "One tag per page, centred");
  auto* palette = c->add_option("--palette", o->palette, "Built-in palette: default, iccv17")
                      ->capture_default_str();
  c->add_option("--palette-file", o->palette_file, "Palette JSON file (docs/palettes.md)")
      ->excludes(palette);
  c->add_option("--color-lut", o->color_lut,
                "3D LUT (.cube) applied to the palette's sRGB, e.g. from 'chromatag calibrate'");
  c->add_option("--format", o->format, "pdf, svg or png (default: from the output's extension)")
      ->check(CLI::IsMember({"pdf", "svg", "png"}));
  c->add_option("--dpi", o->dpi, "PNG resolution in pixels per inch")->capture_default_str();
  c->add_option("-o,--output", o->output, "Output file; the sidecar goes beside it as .json")
      ->required();
  c->callback([o, action] { *action = [o] { return RunGenerate(*o); }; });
}

}  // namespace chromatag::cli
