// The sidecar JSON: what was printed where (docs/generator.md, "Sidecar").
#include <cmath>
#include <nlohmann/json.hpp>

#include "chromatag/families/version.h"
#include "sheet_internal.h"

namespace chromatag::internal {
namespace {

using Json = nlohmann::ordered_json;

// Micrometre precision: far below what a printer holds, stable in text.
double Round3(double mm) { return std::round(mm * 1000.0) / 1000.0; }

std::string BaseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

Json PaletteJson(const Palette& palette, const TagColors& written) {
  Json lab = Json::object();
  Json srgb = Json::object();
  Json printed = Json::object();
  for (Shade shade : kAllShades) {
    const Lab& v = palette[shade];
    lab[ShadeName(shade)] = {v.L, v.a, v.b};
    srgb[ShadeName(shade)] = ToHex(palette.Srgb8(shade));
    printed[ShadeName(shade)] = ToHex(ToRgb8(written[shade]));
  }
  return {{"name", palette.name}, {"lab", lab}, {"srgb", srgb}, {"written_rgb", printed}};
}

}  // namespace

std::string SidecarJson(const SheetOptions& options, const SheetLayout& layout,
                        const std::vector<OutputFile>& page_files) {
  const TagColors written = SheetColors(options);
  Json files = Json::array();
  for (const auto& file : page_files) {
    files.push_back({{"path", BaseName(file.path)}, {"sha256", Sha256Hex(file.contents)}});
  }
  Json tags = Json::array();
  for (const PlacedTag& tag : layout.tags) {
    Json corners = Json::array();
    for (const auto& corner : tag.corners_mm)
      corners.push_back({Round3(corner[0]), Round3(corner[1])});
    tags.push_back({{"id", tag.id},
                    {"page", tag.page + 1},
                    {"center_mm", {Round3(tag.center_mm[0]), Round3(tag.center_mm[1])}},
                    {"corners_mm", corners}});
  }
  Json root = {
      {"schema", "chromatag-layout"},
      {"schema_version", 1},
      {"tool", {{"name", "chromatag"}, {"version", kVersion}}},
      {"family", options.family->name()},
      {"tag_size_mm", options.tag_size_mm},
      {"cell_size_mm", options.tag_size_mm / options.family->black_square_cells()},
      {"quiet_zone_cells", options.tag.quiet_zone_cells},
      {"cut_ring", options.tag.cut_ring},
      {"crop_marks", options.crop_marks},
      {"label", options.label && !options.board},
      {"palette", PaletteJson(options.palette, written)},
      {"color_lut", options.color_lut ? Json(BaseName(options.color_lut->path())) : Json(nullptr)},
      {"page",
       {{"name", options.page.name},
        {"width_mm", options.page.width_mm},
        {"height_mm", options.page.height_mm},
        {"margin_mm", options.margin_mm},
        {"count", layout.num_pages}}},
      {"format", SheetFormatName(options.format)},
      {"dpi", options.format == SheetFormat::kPng ? Json(options.dpi) : Json(nullptr)},
      {"files", files},
      {"tags", tags}};
  if (options.board) {
    // The board frame (docs/pose.md): origin on the page, x right, y up the
    // page, z out of it.
    root["board"] = {
        {"columns", options.board->columns},
        {"rows", options.board->rows},
        {"spacing_mm", Round3(options.board->spacing_mm)},
        {"origin_mm", {Round3(layout.board_origin_mm[0]), Round3(layout.board_origin_mm[1])}}};
  }
  return root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace chromatag::internal
