// FamiliesJson and PalettesJson (listing_json.h).
#include <nlohmann/json.hpp>

#include "chromatag/families/listing_json.h"

namespace chromatag {
namespace {

// nlohmann::json: keys in alphabetical order, as the CLI has always written them.
using Json = nlohmann::json;

std::string Dump(const Json& json) {
  return json.dump(2, ' ', false, Json::error_handler_t::replace);
}

Json FamilyObject(const TagFamily& family, const CodeDecoder& decoder) {
  Json rejected = Json::array();
  for (const auto& r : family.rejected_ids())
    rejected.push_back({{"id", r.id}, {"reason", r.reason}});
  return {{"family", family.name()},
          {"payload_width", family.payload_width()},
          {"bits", family.num_bits()},
          {"red_cells", family.num_red_cells()},
          {"green_cells", family.num_green_cells()},
          {"black_square_cells", family.black_square_cells()},
          {"apriltag_ids", family.num_apriltag_ids()},
          {"kept_ids", family.kept_ids()},
          {"rejected_ids", rejected},
          {"min_hamming", family.min_hamming()},
          {"apriltag_min_hamming", family.apriltag_min_hamming()},
          {"decoding_radius", decoder.radius()},
          {"max_safe_radius", family.max_safe_radius()},
          {"decoder_table_bytes", decoder.memory_bytes()}};
}

Json PaletteObject(const Palette& palette) {
  Json shades = Json::object();
  for (Shade shade : kAllShades) {
    const Lab& lab = palette[shade];
    const Rgb8 rgb = palette.Srgb8(shade);
    shades[ShadeName(shade)] = {
        {"lab", {lab.L, lab.a, lab.b}}, {"srgb", {rgb.r, rgb.g, rgb.b}}, {"hex", ToHex(rgb)}};
  }
  Json checks = Json::array();
  for (const auto& check : CheckPalette(palette)) {
    checks.push_back(
        {{"id", check.id},
         {"level", check.level == PaletteCheck::Level::kRequired ? "required" : "recommended"},
         {"description", check.description},
         {"passed", check.passed},
         {"detail", check.detail}});
  }
  return {{"name", palette.name},
          {"description", palette.description},
          {"shades", shades},
          {"checks", checks}};
}

}  // namespace

std::string FamiliesJson(
    const std::vector<std::pair<const TagFamily*, const CodeDecoder*>>& families) {
  Json all = Json::array();
  for (const auto& [family, decoder] : families) all.push_back(FamilyObject(*family, *decoder));
  return Dump(Json{{"families", all}});
}

std::string PalettesJson(const std::vector<Palette>& palettes) {
  Json all = Json::array();
  for (const Palette& palette : palettes) all.push_back(PaletteObject(palette));
  return Dump(Json{{"palettes", all}});
}

}  // namespace chromatag
