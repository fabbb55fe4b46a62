#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "chromatag/families/input_file.h"
#include "chromatag/generator/json_fields.h"
#include "chromatag/generator/sidecar.h"

namespace chromatag {
namespace {

using json = nlohmann::json;

using json_fields::FieldError;
using json_fields::Integer;
using json_fields::Member;
using json_fields::Number;
using json_fields::Point;
using json_fields::String;

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
  if (!FormatFromPath("x." + format)) throw FieldError{"unknown format \"" + format + "\""};
  record.format = *FormatFromPath("x." + format);
  if (record.format == SheetFormat::kPng) record.dpi = Number(root, "dpi");

  const json& palette = Member(root, "palette");
  json palette_file = {{"name", String(palette, "name")}, {"lab", Member(palette, "lab")}};
  auto parsed = ParsePalette(palette_file.dump(), "sidecar", &error);
  if (!parsed) throw FieldError{error};
  record.palette = *parsed;

  for (const json& file : Member(root, "files")) {
    // A plain file name beside the sidecar: a sidecar must not make verify
    // read (and hash) ../../etc/passwd or any file outside its folder.
    const std::string name = String(file, "path");
    if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\\') != std::string::npos) {
      throw FieldError{"a file's \"path\" must be a file name beside the sidecar, not \"" + name +
                       "\""};
    }
    record.files.push_back({folder + name, String(file, "sha256")});
  }
  const size_t expected_files = record.format == SheetFormat::kPdf ? 1 : record.num_pages;
  if (record.files.size() != expected_files) {
    throw FieldError{"\"files\" must list " + std::to_string(expected_files) + " file(s)"};
  }
  for (const json& tag : Member(root, "tags")) {
    PlacedTag placed;
    placed.id = Integer(tag, "id", 0, 1 << 20);
    if (!record.family->IsValidId(placed.id, &error)) throw FieldError{error};
    placed.page = Integer(tag, "page", 1, 100000) - 1;
    if (placed.page < 0 || placed.page >= record.num_pages) {
      throw FieldError{"tag ID " + std::to_string(placed.id) + " is on a page that does not exist"};
    }
    placed.center_mm = Point(Member(tag, "center_mm"));
    const json& corners = Member(tag, "corners_mm");
    if (!corners.is_array() || corners.size() != 4) throw FieldError{"a tag needs 4 corners"};
    for (int i = 0; i < 4; ++i) placed.corners_mm[i] = Point(corners[i]);
    record.tags.push_back(placed);
  }
  record.board_origin_mm = {0.0, record.page.height_mm};
  if (root.contains("board")) {
    const json& board = Member(root, "board");
    BoardGrid grid;
    grid.columns = Integer(board, "columns", 1, 100);
    grid.rows = Integer(board, "rows", 1, 100);
    grid.spacing_mm = Number(board, "spacing_mm");
    record.board = grid;
    record.board_origin_mm = Point(Member(board, "origin_mm"));
    if (record.num_pages != 1 ||
        record.tags.size() != static_cast<size_t>(grid.columns) * grid.rows)
      throw FieldError{"a board is one page of columns x rows tags"};
    if (!(grid.spacing_mm > 0)) throw FieldError{"a board's spacing_mm must be positive"};
    // The tags on the grid and the origin at the bottom-left tag's corner,
    // within the sidecar's 1 um rounding and, for PNG, half a pixel of
    // snapping to whole pixels.
    const double tolerance = 0.002 + (record.format == SheetFormat::kPng ? 12.7 / record.dpi : 0);
    const double pitch = record.tag_size_mm + grid.spacing_mm;
    const auto& first = record.tags[0].corners_mm[0];
    for (size_t i = 0; i < record.tags.size(); ++i) {
      const auto& corner = record.tags[i].corners_mm[0];
      const double x = first[0] + static_cast<double>(i % grid.columns) * pitch;
      const double y = first[1] + static_cast<double>(i / grid.columns) * pitch;
      if (std::fabs(corner[0] - x) > tolerance || std::fabs(corner[1] - y) > tolerance)
        throw FieldError{"the board's tags are not on its columns x rows grid"};
    }
    const auto& origin = record.tags[(grid.rows - 1) * grid.columns].corners_mm[3];
    if (std::fabs(origin[0] - record.board_origin_mm[0]) > 0.002 ||
        std::fabs(origin[1] - record.board_origin_mm[1]) > 0.002)
      throw FieldError{"the board's origin_mm is not the bottom-left tag's bottom-left corner"};
  }
  return record;
}

}  // namespace

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

}  // namespace chromatag
