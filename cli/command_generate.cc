#include <iostream>

#include "chromatag/families/palette.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/sheet_request.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

struct GenerateOptions {
  SheetRequest request;
  bool no_label = false;
  std::string output;
};

int RunGenerate(const GenerateOptions& options) {
  SheetOptions sheet;
  std::string error;
  SheetRequest request = options.request;
  request.label = !options.no_label;
  if (!ToSheetOptions(request, options.output, &sheet, &error)) return Fail("generate", error);
  const auto layout = LayoutSheet(sheet, &error);
  if (!layout) return Fail("generate", error);
  std::vector<std::string> written;
  if (!WriteSheet(sheet, options.output, &error, &written)) return Fail("generate", error);
  if (sheet.board) {
    std::cout << "Wrote a " << sheet.board->columns << " x " << sheet.board->rows << " board of "
              << sheet.family->name() << " tags of " << sheet.tag_size_mm << " mm, "
              << sheet.board->spacing_mm << " mm apart, on one " << sheet.page.name
              << " page, palette " << sheet.palette.name
              << (sheet.color_lut ? " through " + sheet.color_lut->path() : "")
              << "; its sidecar is the board file (detect --board):\n";
    for (const auto& path : written) std::cout << "  " << path << "\n";
    return kExitOk;
  }
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
  c->add_option("--family", o->request.family, "Tag family")
      ->capture_default_str()
      ->transform(FamilyPrefix())
      ->check(CLI::IsMember(TagFamily::Names()));
  auto* ids = c->add_option("--ids", o->request.ids, "Tag IDs, e.g. 0-9,12,20-27");
  c->add_flag("--all", o->request.all, "Every kept ID of the family")->excludes(ids);
  c->add_option("--size", o->request.size,
                "Tag size: side of the black square (mm, cm, m, in); default 40mm, or with "
                "--board the largest that fits the page");
  c->add_option(
       "--page", o->request.page,
       "a4, a3, letter, legal (each also as a4-landscape, a4-portrait: not turned to fit a "
       "board), or WxH with a unit (210x297mm)")
      ->capture_default_str();
  c->add_option("--margin", o->request.margin, "Blank border on every side of the page")
      ->capture_default_str();
  c->add_option("--gap", o->request.gap, "Space between tags")->capture_default_str();
  c->add_option("--quiet-zone", o->request.quiet_zone,
                "White ring around the black square, in cells")
      ->capture_default_str()
      ->check(CLI::Range(1, 20));
  c->add_flag("--cut-ring", o->request.cut_ring, "A light grey ring to cut along");
  c->add_flag("--crop-marks", o->request.crop_marks, "Crop marks at the corners of each tag");
  c->add_flag("--no-label", o->no_label, "No 'family ID size' line under the tags");
  c->add_flag("--one-per-page", o->request.one_per_page, "One tag per page, centred");
  c->add_option("--board", o->request.board,
                "Lay the tags out as a board of COLSxROWS (e.g. 6x4) with its origin and axes "
                "marked; without --ids, the family's first kept IDs. The sidecar is the board "
                "file for 'detect --board' (docs/pose.md)");
  c->add_option("--spacing", o->request.spacing,
                "Between a board's neighbouring black squares (default: a quarter of the tag "
                "size, at least the quiet zone)");
  auto* palette =
      c->add_option("--palette", o->request.palette, "Built-in palette: default, iccv17")
          ->capture_default_str();
  c->add_option("--palette-file", o->request.palette_file, "Palette JSON file (docs/palettes.md)")
      ->excludes(palette);
  c->add_option("--color-lut", o->request.color_lut,
                "3D LUT (.cube) applied to the palette's sRGB, e.g. from 'chromatag calibrate'");
  c->add_option("--format", o->request.format,
                "pdf, svg or png (default: from the output's extension)")
      ->check(CLI::IsMember({"pdf", "svg", "png"}));
  c->add_option("--dpi", o->request.dpi, "PNG resolution in pixels per inch")
      ->capture_default_str();
  c->add_option("-o,--output", o->output, "Output file; the sidecar goes beside it as .json")
      ->required();
  c->callback([o, action] { *action = [o] { return RunGenerate(*o); }; });
}

}  // namespace chromatag::cli
