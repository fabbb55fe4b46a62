#include "chromatag/layout/sheet_record.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "chromatag/base/input_file.h"
#include "chromatag/base/sha256.h"
#include "chromatag/families/version.h"
#include "json_fields.h"

namespace chromatag {
namespace {

using json = nlohmann::json;
using Json = nlohmann::ordered_json;

using json_fields::FieldError;
using json_fields::Integer;
using json_fields::Member;
using json_fields::Number;
using json_fields::Point;
using json_fields::String;

// Micrometre precision: far below what a printer holds, stable in text.
double Round3(double mm) { return std::round(mm * 1000.0) / 1000.0; }

std::string BaseName(const std::string& path) { return path.substr(path.find_last_of('/') + 1); }

Json PaletteJson(const SheetRecord& record) {
  Json lab = Json::object();
  Json srgb = Json::object();
  Json printed = Json::object();
  for (Shade shade : kAllShades) {
    const Lab& v = record.palette[shade];
    lab[ShadeName(shade)] = {v.L, v.a, v.b};
    srgb[ShadeName(shade)] = ToHex(record.palette.Srgb8(shade));
    printed[ShadeName(shade)] = ToHex(record.written_rgb[static_cast<int>(shade)]);
  }
  return {{"name", record.palette.name}, {"lab", lab}, {"srgb", srgb}, {"written_rgb", printed}};
}

Json TagsJson(const std::vector<PlacedTag>& placed) {
  Json tags = Json::array();
  for (const PlacedTag& tag : placed) {
    Json corners = Json::array();
    for (const auto& corner : tag.corners_mm)
      corners.push_back({Round3(corner[0]), Round3(corner[1])});
    tags.push_back({{"id", tag.id},
                    {"page", tag.page + 1},
                    {"center_mm", {Round3(tag.center_mm[0]), Round3(tag.center_mm[1])}},
                    {"corners_mm", corners}});
  }
  return tags;
}

// The files a sidecar lists: plain names beside it, one PDF or a file a page.
void ParseFiles(const json& root, const std::string& folder, SheetRecord* record) {
  for (const json& file : Member(root, "files")) {
    // A plain file name beside the sidecar: a sidecar must not make verify
    // read (and hash) ../../etc/passwd or any file outside its folder.
    const std::string name = String(file, "path");
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\\') != std::string::npos) {
      throw FieldError{"a file's \"path\" must be a file name beside the sidecar, not \"" + name +
                       "\""};
    }
    record->files.push_back({folder + name, String(file, "sha256")});
  }
  const size_t expected_files = record->format == SheetFormat::kPdf ? 1 : record->num_pages;
  if (record->files.size() != expected_files) {
    throw FieldError{"\"files\" must list " + std::to_string(expected_files) + " file(s)"};
  }
}

void ParseTags(const json& root, SheetRecord* record) {
  std::string error;
  for (const json& tag : Member(root, "tags")) {
    PlacedTag placed;
    placed.id = Integer(tag, "id", 0, 1 << 20);
    if (!record->family->IsValidId(placed.id, &error)) throw FieldError{error};
    placed.page = Integer(tag, "page", 1, 100000) - 1;
    if (placed.page < 0 || placed.page >= record->num_pages) {
      throw FieldError{"tag ID " + std::to_string(placed.id) + " is on a page that does not exist"};
    }
    placed.center_mm = Point(Member(tag, "center_mm"));
    const json& corners = Member(tag, "corners_mm");
    if (!corners.is_array() || corners.size() != 4) throw FieldError{"a tag needs 4 corners"};
    for (int i = 0; i < 4; ++i) placed.corners_mm[i] = Point(corners[i]);
    record->tags.push_back(placed);
  }
}

// A board's grid and origin, checked against its tags.
void ParseBoard(const json& root, SheetRecord* record) {
  record->board_origin_mm = {0.0, record->page.height_mm};
  if (root.contains("board")) {
    const json& board = Member(root, "board");
    BoardGrid grid;
    grid.columns = Integer(board, "columns", 1, 100);
    grid.rows = Integer(board, "rows", 1, 100);
    grid.spacing_mm = Number(board, "spacing_mm");
    record->board = grid;
    record->board_origin_mm = Point(Member(board, "origin_mm"));
    if (record->num_pages != 1 ||
        record->tags.size() != static_cast<size_t>(grid.columns) * grid.rows)
      throw FieldError{"a board is one page of columns x rows tags"};
    if (!(grid.spacing_mm > 0)) throw FieldError{"a board's spacing_mm must be positive"};
    // The tags on the grid and the origin at the bottom-left tag's corner,
    // within the sidecar's 1 um rounding and, for PNG, half a pixel of
    // snapping to whole pixels.
    const double tolerance = 0.002 + (record->format == SheetFormat::kPng ? 12.7 / record->dpi : 0);
    const double pitch = record->tag_size_mm + grid.spacing_mm;
    const auto& first = record->tags[0].corners_mm[0];
    for (size_t i = 0; i < record->tags.size(); ++i) {
      const auto& corner = record->tags[i].corners_mm[0];
      const double x = first[0] + static_cast<double>(i % grid.columns) * pitch;
      const double y = first[1] + static_cast<double>(i / grid.columns) * pitch;
      if (std::fabs(corner[0] - x) > tolerance || std::fabs(corner[1] - y) > tolerance)
        throw FieldError{"the board's tags are not on its columns x rows grid"};
    }
    const auto& origin = record->tags[(grid.rows - 1) * grid.columns].corners_mm[3];
    if (std::fabs(origin[0] - record->board_origin_mm[0]) > 0.002 ||
        std::fabs(origin[1] - record->board_origin_mm[1]) > 0.002)
      throw FieldError{"the board's origin_mm is not the bottom-left tag's bottom-left corner"};
  }
}

SheetRecord Parse(const json& root, const std::string& folder) {
  if (String(root, "schema") != "chromatag-layout") {
    throw FieldError{"not a ChromaTag sidecar (schema must be \"chromatag-layout\")"};
  }
  if (Number(root, "schema_version") != 1) {
    throw FieldError{"unsupported schema_version (this chromatag reads version 1)"};
  }
  SheetRecord record;
  std::string error;
  record.family = TagFamily::Load(String(root, "family"), &error);
  if (!record.family) throw FieldError{error};
  record.tag_size_mm = Number(root, "tag_size_mm");
  record.quiet_zone_cells = Integer(root, "quiet_zone_cells", 1, 20);
  const json& page = Member(root, "page");
  record.page = {String(page, "name"), Number(page, "width_mm"), Number(page, "height_mm")};
  record.num_pages = Integer(page, "count", 1, 100000);
  const std::string format = String(root, "format");
  const auto sheet_format = SheetFormatFromName(format);
  if (!sheet_format) throw FieldError{"unknown format \"" + format + "\""};
  record.format = *sheet_format;
  if (record.format == SheetFormat::kPng) record.dpi = Number(root, "dpi");

  const json& palette = Member(root, "palette");
  json palette_file = {{"name", String(palette, "name")}, {"lab", Member(palette, "lab")}};
  auto parsed = ParsePalette(palette_file.dump(), "sidecar", &error);
  if (!parsed) throw FieldError{error};
  record.palette = *parsed;

  ParseFiles(root, folder, &record);
  ParseTags(root, &record);
  ParseBoard(root, &record);
  return record;
}

}  // namespace

const char* SheetFormatName(SheetFormat format) {
  switch (format) {
    case SheetFormat::kPdf:
      return "pdf";
    case SheetFormat::kSvg:
      return "svg";
    case SheetFormat::kPng:
      return "png";
  }
  return "?";
}

std::optional<SheetFormat> SheetFormatFromName(const std::string& name) {
  for (SheetFormat format : {SheetFormat::kPdf, SheetFormat::kSvg, SheetFormat::kPng}) {
    if (name == SheetFormatName(format)) return format;
  }
  return std::nullopt;
}

std::string SidecarPath(const std::string& output_path) { return output_path + ".json"; }

std::string SidecarJson(const SheetRecord& record) {
  Json files = Json::array();
  for (const auto& file : record.files) {
    files.push_back({{"path", BaseName(file.path)}, {"sha256", file.sha256}});
  }
  const TagFamily& family = *record.family;
  Json root = {{"schema", "chromatag-layout"},
               {"schema_version", 1},
               {"tool", {{"name", "chromatag"}, {"version", kVersion}}},
               {"family", family.name()},
               {"tag_size_mm", record.tag_size_mm},
               {"cell_size_mm", record.tag_size_mm / family.black_square_cells()},
               {"quiet_zone_cells", record.quiet_zone_cells},
               {"cut_ring", record.cut_ring},
               {"crop_marks", record.crop_marks},
               {"label", record.label},
               {"palette", PaletteJson(record)},
               {"color_lut", record.color_lut.empty() ? Json(nullptr) : Json(record.color_lut)},
               {"page",
                {{"name", record.page.name},
                 {"width_mm", record.page.width_mm},
                 {"height_mm", record.page.height_mm},
                 {"margin_mm", record.margin_mm},
                 {"count", record.num_pages}}},
               {"format", SheetFormatName(record.format)},
               {"dpi", record.format == SheetFormat::kPng ? Json(record.dpi) : Json(nullptr)},
               {"files", files},
               {"tags", TagsJson(record.tags)}};
  if (record.board) {
    // The board frame (docs/pose.md): origin on the page, x right, y up the
    // page, z out of it.
    root["board"] = {
        {"columns", record.board->columns},
        {"rows", record.board->rows},
        {"spacing_mm", Round3(record.board->spacing_mm)},
        {"origin_mm", {Round3(record.board_origin_mm[0]), Round3(record.board_origin_mm[1])}}};
  }
  return root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::optional<SheetRecord> ParseSidecar(const std::string& text, const std::string& folder,
                                        std::string* error) {
  if (JsonDeeperThan(text, kMaxJsonDepth)) {
    if (error) *error = "nests deeper than any sidecar does";
    return std::nullopt;
  }
  const json root = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded()) {
    if (error) *error = "not valid JSON";
    return std::nullopt;
  }
  try {
    return Parse(root, folder);
  } catch (const FieldError& e) {
    if (error) *error = e.message;
  } catch (const json::exception& e) {
    if (error) *error = std::string("malformed (") + e.what() + ")";
  }
  return std::nullopt;
}

std::optional<SheetRecord> ReadSidecar(const std::string& path, std::string* error) {
  const auto text = ReadInputFile(path, "sidecar", kMaxJsonFileBytes, error);
  if (!text) return std::nullopt;
  const auto slash = path.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  std::string why;
  auto record = ParseSidecar(*text, folder, &why);
  if (!record) {
    if (error) *error = "sidecar '" + path + "': " + why;
    return std::nullopt;
  }
  record->sidecar_path = path;
  return record;
}

std::optional<std::string> ReadSidecarOfSheet(const std::string& sheet_path,
                                              const std::string& kind, std::string* sidecar_path,
                                              std::string* error) {
  // A sheet PDF or SVG is tens of KiB; a 1200 dpi A3 PNG about 100 MiB.
  const auto sheet = ReadInputFile(sheet_path, kind, std::uintmax_t{512} << 20, error);
  if (!sheet) return std::nullopt;
  const std::string sidecar = SidecarPath(sheet_path);
  if (sidecar_path) *sidecar_path = sidecar;
  auto text = ReadInputFile(sidecar, kind + " sidecar", kMaxJsonFileBytes, error);
  if (!text) {
    if (error) *error += "; chromatag writes it beside the sheet";
    return std::nullopt;
  }
  Json root;
  if (JsonDeeperThan(*text, kMaxJsonDepth) ||
      (root = Json::parse(*text, nullptr, false)).is_discarded() || !root.is_object()) {
    if (error) *error = kind + " sidecar '" + sidecar + "': not valid JSON";
    return std::nullopt;
  }
  const std::string name = BaseName(sheet_path);
  std::string listed;
  const Json files = root.value("files", Json::array());
  for (const Json& file : files.is_array() ? files : Json::array()) {
    if (!file.is_object() || !file.contains("path") || !file["path"].is_string()) continue;
    if (file["path"].get<std::string>() != name) {
      if (listed.empty()) listed = file["path"].get<std::string>();
      continue;
    }
    if (!file.contains("sha256") || !file["sha256"].is_string() ||
        file["sha256"].get<std::string>() != Sha256Hex(*sheet)) {
      if (error)
        *error = kind + " '" + sheet_path +
                 "' was changed after it was generated: its SHA-256 differs from its sidecar's";
      return std::nullopt;
    }
    return text;
  }
  if (error)
    *error = "sidecar '" + sidecar + "' does not describe '" + sheet_path + "' (it lists " +
             (listed.empty() ? "no file" : "'" + listed + "'") +
             "); give the sheet its own sidecar, or the sidecar itself";
  return std::nullopt;
}

}  // namespace chromatag
