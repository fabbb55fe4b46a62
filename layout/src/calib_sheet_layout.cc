// The calibration sheet's sidecar (calib_sheet_layout.h).
#include "chromatag/layout/calib_sheet_layout.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "chromatag/base/input_file.h"
#include "chromatag/base/sha256.h"
#include "chromatag/families/family.h"
#include "chromatag/families/version.h"
#include "chromatag/layout/sheet_record.h"
#include "json_fields.h"

namespace chromatag {
namespace {

using Json = nlohmann::ordered_json;

// Micrometre precision, as the generator's sidecar.
double Round3(double mm) { return std::round(mm * 1000.0) / 1000.0; }
double Round4(double v) { return std::round(v * 10000.0) / 10000.0; }

std::string BaseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

Json LabJson(const Lab& lab) { return {Round4(lab.L), Round4(lab.a), Round4(lab.b)}; }

using ParseError = json_fields::FieldError;
using json_fields::Integer;
using json_fields::Member;
using json_fields::Number;
using json_fields::Point;
using json_fields::String;

Lab ParseLab(const Json& value) {
  if (!value.is_array() || value.size() != 3) throw ParseError{"a colour must be [L*, a*, b*]"};
  for (const auto& v : value) {
    if (!v.is_number()) throw ParseError{"a colour must be [L*, a*, b*] numbers"};
  }
  Lab lab{value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
  if (!(lab.L >= 0 && lab.L <= 100 && std::abs(lab.a) <= 128 && std::abs(lab.b) <= 128))
    throw ParseError{"a colour is out of range (L* in [0, 100], a* and b* in [-128, 128])"};
  return lab;
}

Rgb8 ParseHex(const std::string& text) {
  if (text.size() != 7 || text[0] != '#' ||
      text.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
    throw ParseError{"an RGB value must be \"#rrggbb\", got \"" + text + "\""};
  const unsigned long v = std::stoul(text.substr(1), nullptr, 16);
  return Rgb8{static_cast<uint8_t>(v >> 16), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v)};
}

PatchKind ParseKind(const std::string& name) {
  for (PatchKind kind :
       {PatchKind::kPaper, PatchKind::kPalette, PatchKind::kGrey, PatchKind::kCandidate}) {
    if (name == PatchKindName(kind)) return kind;
  }
  throw ParseError{"unknown patch kind \"" + name + "\" (paper, palette, grey, candidate)"};
}

Patch ParsePatch(const Json& item, const PageSize& page) {
  Patch patch;
  patch.kind = ParseKind(String(item, "kind"));
  if (patch.kind == PatchKind::kPalette || patch.kind == PatchKind::kCandidate) {
    const auto shade = ShadeFromName(String(item, "shade"));
    if (!shade) throw ParseError{"unknown shade \"" + String(item, "shade") + "\""};
    patch.shade = *shade;
  }
  patch.lab = ParseLab(Member(item, "lab"));
  patch.rgb = ParseHex(String(item, "rgb"));
  patch.origin_mm = Point(Member(item, "origin_mm"));
  patch.size_mm = Number(item, "size_mm");
  const auto slot = Member(item, "slot");
  const auto index = [](const Json& v) {
    return v.is_number_integer() && v.get<long long>() >= 0 && v.get<long long>() < 10000;
  };
  if (!slot.is_array() || slot.size() != 2 || !index(slot[0]) || !index(slot[1]))
    throw ParseError{"\"slot\" must be [row, column], each in [0, 10000)"};
  patch.row = slot[0].get<int>();
  patch.col = slot[1].get<int>();
  if (!(patch.size_mm > 0) || patch.origin_mm[0] < 0 || patch.origin_mm[1] < 0 ||
      patch.origin_mm[0] + patch.size_mm > page.width_mm ||
      patch.origin_mm[1] + patch.size_mm > page.height_mm)
    throw ParseError{"a patch lies outside the page"};
  return patch;
}

CalibSheetLayout Parse(const Json& root) {
  if (String(root, "schema") != kCalibSheetSchema)
    throw ParseError{std::string("not a calibration sheet sidecar (schema must be \"") +
                     kCalibSheetSchema + "\"; tag sheets from 'chromatag generate' are not)"};
  if (Number(root, "schema_version") != kCalibSheetSchemaVersion)
    throw ParseError{"unsupported schema_version (this chromatag reads version 1)"};
  CalibSheetLayout layout;
  const double id = Number(root, "sheet_id");
  if (!(id >= 1 && id <= 65535 && id == std::floor(id)))
    throw ParseError{"\"sheet_id\" must be an integer in [1, 65535]"};
  layout.sheet_id = static_cast<int>(id);
  const Json& page = Member(root, "page");
  layout.page = {String(page, "name"), Number(page, "width_mm"), Number(page, "height_mm")};
  if (!(layout.page.width_mm > 0 && layout.page.height_mm > 0))
    throw ParseError{"the page size must be positive"};
  std::string error;
  const auto palette = ParsePalette(Member(root, "palette").dump(), "sheet", &error);
  if (!palette) throw ParseError{"palette: " + error};
  layout.palette = *palette;
  layout.family = String(root, "family");
  const auto family = TagFamily::Load(layout.family, &error);
  if (!family) throw ParseError{error};
  layout.tag_size_mm = Number(root, "tag_size_mm");
  // calib-sheet's own range: the corner tags' black squares, in mm.
  if (!(layout.tag_size_mm >= 10 && layout.tag_size_mm <= 60))
    throw ParseError{"\"tag_size_mm\" must be in [10, 60]"};
  // The page files: names beside the sidecar, never paths.
  if (root.contains("files")) {
    const Json& files = root["files"];
    if (!files.is_array()) throw ParseError{"\"files\" must be a list"};
    for (const Json& file : files) {
      const std::string name = String(file, "path");
      if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
        throw ParseError{"a file must be named by its base name beside the sidecar, not '" + name +
                         "'"};
    }
  }
  const Json& grid = Member(root, "grid");
  layout.rows = Integer(grid, "rows", 1, 10000);
  layout.columns = Integer(grid, "columns", 1, 10000);
  const Json& tags = Member(root, "corner_tags");
  if (!tags.is_array() || tags.size() != 4) throw ParseError{"\"corner_tags\" must hold 4 tags"};
  for (int k = 0; k < 4; ++k) {
    CornerTag& tag = layout.tags[k];
    tag.id = Integer(tags[k], "id", 0, 1 << 20);
    if (!family->IsValidId(tag.id, &error)) throw ParseError{"corner tag: " + error};
    if (String(tags[k], "corner") != kCornerNames[k])
      throw ParseError{"corner tags must be listed top-left, top-right, bottom-right, bottom-left"};
    const Json& corners = Member(tags[k], "corners_mm");
    if (!corners.is_array() || corners.size() != 4)
      throw ParseError{"a corner tag needs 4 corners_mm"};
    for (int i = 0; i < 4; ++i) tag.corners_mm[i] = Point(corners[i]);
  }
  const Json& patches = Member(root, "patches");
  if (!patches.is_array() || patches.empty()) throw ParseError{"\"patches\" must be a list"};
  for (const Json& item : patches) {
    layout.patches.push_back(ParsePatch(item, layout.page));
    layout.patches.back().index = static_cast<int>(layout.patches.size()) - 1;
  }
  return layout;
}

}  // namespace

const char* PatchKindName(PatchKind kind) {
  switch (kind) {
    case PatchKind::kPaper:
      return "paper";
    case PatchKind::kPalette:
      return "palette";
    case PatchKind::kGrey:
      return "grey";
    case PatchKind::kCandidate:
      return "candidate";
  }
  return "?";
}

std::string CalibSidecarJson(const CalibSheetLayout& layout,
                             const std::vector<OutputFile>& page_files) {
  Json files = Json::array();
  for (const auto& file : page_files)
    files.push_back({{"path", BaseName(file.path)}, {"sha256", Sha256Hex(file.contents)}});
  Json tags = Json::array();
  for (int k = 0; k < 4; ++k) {
    Json corners = Json::array();
    for (const auto& c : layout.tags[k].corners_mm) corners.push_back({Round3(c[0]), Round3(c[1])});
    tags.push_back(
        {{"corner", kCornerNames[k]}, {"id", layout.tags[k].id}, {"corners_mm", corners}});
  }
  Json patches = Json::array();
  for (const Patch& patch : layout.patches) {
    Json item = {{"index", patch.index}, {"kind", PatchKindName(patch.kind)}};
    if (patch.kind == PatchKind::kPalette) item["shade"] = ShadeName(patch.shade);
    if (patch.kind == PatchKind::kCandidate) item["shade"] = ShadeName(patch.shade);
    item["lab"] = LabJson(patch.lab);
    item["rgb"] = ToHex(patch.rgb);
    item["slot"] = {patch.row, patch.col};
    item["origin_mm"] = {Round3(patch.origin_mm[0]), Round3(patch.origin_mm[1])};
    item["size_mm"] = Round3(patch.size_mm);
    patches.push_back(item);
  }
  Json palette = Json::parse(PaletteToJson(layout.palette));
  Json root = {{"schema", kCalibSheetSchema},
               {"schema_version", kCalibSheetSchemaVersion},
               {"tool", {{"name", "chromatag"}, {"version", kVersion}}},
               {"sheet_id", layout.sheet_id},
               {"page",
                {{"name", layout.page.name},
                 {"width_mm", layout.page.width_mm},
                 {"height_mm", layout.page.height_mm}}},
               {"palette", palette},
               {"family", layout.family},
               {"tag_size_mm", layout.tag_size_mm},
               {"grid", {{"rows", layout.rows}, {"columns", layout.columns}}},
               {"files", files},
               {"corner_tags", tags},
               {"patches", patches}};
  return root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::optional<CalibSheetLayout> ParseCalibSidecar(const std::string& text, std::string* error) {
  if (JsonDeeperThan(text, kMaxJsonDepth)) {
    if (error) *error = "nests deeper than a calibration sidecar does";
    return std::nullopt;
  }
  try {
    return Parse(Json::parse(text));
  } catch (const Json::exception& e) {
    if (error) *error = std::string("not valid JSON: ") + e.what();
  } catch (const ParseError& e) {
    if (error) *error = e.message;
  }
  return std::nullopt;
}

std::optional<CalibSheetLayout> ReadCalibSidecar(const std::string& path, std::string* error) {
  const auto text = ReadInputFile(path, "calibration sheet sidecar", kMaxJsonFileBytes, error);
  if (!text) return std::nullopt;
  std::string why;
  auto layout = ParseCalibSidecar(*text, &why);
  if (!layout && error) *error = "calibration sheet sidecar '" + path + "': " + why;
  return layout;
}

std::optional<CalibSheetLayout> ReadCalibSheet(const std::string& path, std::string* error) {
  if (LowerExtension(path) == ".json") return ReadCalibSidecar(path, error);
  std::string sidecar;
  const auto text = ReadSidecarOfSheet(path, "calibration sheet", &sidecar, error);
  if (!text) return std::nullopt;
  std::string why;
  auto layout = ParseCalibSidecar(*text, &why);
  if (!layout && error) *error = "calibration sheet sidecar '" + sidecar + "': " + why;
  return layout;
}

}  // namespace chromatag
