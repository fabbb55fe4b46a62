#include "chromatag/rig/board_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "bounded_yaml.h"
#include "chromatag/base/input_file.h"
#include "chromatag/layout/calib_sheet_layout.h"

namespace chromatag {
namespace {

// Bundle YAML files are small: a few hundred tags at most.
constexpr std::uintmax_t kMaxBundleFileBytes = 1u << 20;

// The first "tag_bundles" at the top level or one map down (ROS parameter
// files nest the node's parameters under its name).
YAML::Node FindBundles(const YAML::Node& root) {
  if (!root.IsMap()) return YAML::Node();
  if (root["tag_bundles"]) return root["tag_bundles"];
  for (const auto& entry : root) {
    if (entry.second.IsMap()) {
      if (entry.second["tag_bundles"]) return entry.second["tag_bundles"];
      if (entry.second["ros__parameters"] && entry.second["ros__parameters"]["tag_bundles"])
        return entry.second["ros__parameters"]["tag_bundles"];
    }
  }
  return YAML::Node();
}

double Number(const YAML::Node& tag, const char* key, std::optional<double> fallback,
              const std::string& what) {
  const YAML::Node value = tag[key];
  if (!value) {
    if (fallback) return *fallback;
    throw std::runtime_error(what + " has no " + key);
  }
  double number = 0;
  try {
    number = value.as<double>();
  } catch (const YAML::Exception&) {
    throw std::runtime_error(what + ": " + key + " is not a number");
  }
  if (!std::isfinite(number)) throw std::runtime_error(what + ": " + key + " is not finite");
  return number;
}

Board ToBoard(const YAML::Node& bundle, int index) {
  Board board;
  if (bundle["name"]) board.name = bundle["name"].as<std::string>();
  if (board.name.empty()) board.name = "bundle " + std::to_string(index + 1);
  const std::string family = bundle["family"] ? bundle["family"].as<std::string>() : "";
  if (bundle["palette"]) board.palette = bundle["palette"].as<std::string>();
  const YAML::Node layout = bundle["layout"];
  if (!layout || !layout.IsSequence() || layout.size() == 0)
    throw std::runtime_error("bundle '" + board.name + "' has no layout (a list of tags)");
  for (size_t i = 0; i < layout.size(); ++i) {
    const YAML::Node tag = layout[i];
    const std::string what = "bundle '" + board.name + "', tag " + std::to_string(i + 1);
    if (!tag.IsMap()) throw std::runtime_error(what + " is not a map (id, size, x, y, z, ...)");
    BoardTag out;
    const double id = Number(tag, "id", std::nullopt, what);
    if (id != std::floor(id) || id < 0 || id > (1 << 20))
      throw std::runtime_error(what + ": id must be a whole number from 0");
    out.id = static_cast<int>(id);
    out.family = tag["family"] ? tag["family"].as<std::string>() : family;
    if (out.family.rfind("tag", 0) == 0) out.family = out.family.substr(3);  // tag16h5
    if (out.family.empty()) {
      throw std::runtime_error(what +
                               " has no family: give `family: 16h5` (or 36h11) for the "
                               "bundle or the tag");
    }
    out.size = Number(tag, "size", std::nullopt, what);
    // As apriltag_ros: a position left out is 0.
    out.translation = {Number(tag, "x", 0.0, what), Number(tag, "y", 0.0, what),
                       Number(tag, "z", 0.0, what)};
    double q[4] = {Number(tag, "qw", 1.0, what), Number(tag, "qx", 0.0, what),
                   Number(tag, "qy", 0.0, what), Number(tag, "qz", 0.0, what)};
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::fabs(norm - 1.0) < 0.01))
      throw std::runtime_error(what + ": qw, qx, qy, qz must be a unit quaternion");
    for (double& v : q) v /= norm;
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    out.rotation = cv::Matx33d(1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                               2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                               2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y));
    board.tags.push_back(out);
  }
  return board;
}

}  // namespace

std::optional<Board> BoardFromSheet(const SheetRecord& sheet, std::string* error) {
  if (sheet.num_pages != 1) {
    if (error) {
      *error = "a board is one page of tags, and this sheet has " +
               std::to_string(sheet.num_pages) + " pages";
    }
    return std::nullopt;
  }
  Board board;
  // The sheet's name: its sidecar's without ".json".
  board.name = std::filesystem::path(sheet.sidecar_path).stem().string();
  board.palette = sheet.palette.name;
  for (const PlacedTag& placed : sheet.tags) {
    BoardTag tag;
    tag.family = sheet.family->name();
    tag.id = placed.id;
    tag.size = sheet.tag_size_mm / 1000.0;
    // Page millimetres (y down) to board metres (y up), from the origin.
    tag.translation = {(placed.center_mm[0] - sheet.board_origin_mm[0]) / 1000.0,
                       (sheet.board_origin_mm[1] - placed.center_mm[1]) / 1000.0, 0.0};
    board.tags.push_back(tag);
  }
  if (!board.IsValid(error)) return std::nullopt;
  return board;
}

std::optional<Board> BoardFromCalibSheet(const CalibSheetLayout& layout, std::string* error) {
  Board board;
  board.name = "calibration sheet " + std::to_string(layout.sheet_id);
  board.palette = layout.palette.name;
  for (const CornerTag& corner : layout.tags) {
    BoardTag tag;
    tag.family = layout.family;
    tag.id = corner.id;
    tag.size = layout.tag_size_mm / 1000.0;
    double x = 0, y = 0;
    for (const auto& c : corner.corners_mm) {
      x += 0.25 * c[0];
      y += 0.25 * c[1];
    }
    // Page millimetres (y down) to metres from the page's bottom-left corner (y up).
    tag.translation = {x / 1000.0, (layout.page.height_mm - y) / 1000.0, 0.0};
    board.tags.push_back(tag);
  }
  if (!board.IsValid(error)) return std::nullopt;
  return board;
}

std::optional<Board> ParseBundleYaml(const std::string& text, const std::string& name,
                                     std::string* error) {
  const auto fail = [&](const std::string& message) -> std::optional<Board> {
    if (error) *error = message;
    return std::nullopt;
  };
  YAML::Node root;
  try {
    root = internal::LoadBoundedYaml(text);
  } catch (const YAML::Exception& e) {
    return fail("is not valid YAML (" + internal::YamlErrorAt(e) + ")");
  }
  try {
    const YAML::Node bundles = FindBundles(root);
    if (!bundles || !bundles.IsSequence() || bundles.size() == 0)
      return fail("has no tag_bundles (a list of bundles, each with a name and a layout)");
    std::vector<Board> boards;
    for (size_t i = 0; i < bundles.size(); ++i) {
      if (!bundles[i].IsMap()) return fail("has a tag_bundles entry that is not a map");
      boards.push_back(ToBoard(bundles[i], static_cast<int>(i)));
    }
    std::string names;
    for (const Board& b : boards) names += (names.empty() ? "'" : ", '") + b.name + "'";
    const Board* chosen = nullptr;
    if (name.empty()) {
      if (boards.size() > 1)
        return fail("holds " + std::to_string(boards.size()) + " bundles (" + names +
                    "): choose one with FILE#NAME");
      chosen = &boards[0];
    } else {
      for (const Board& b : boards)
        if (b.name == name) chosen = &b;
      if (!chosen) return fail("has no bundle '" + name + "' (it holds " + names + ")");
    }
    std::string why;
    if (!chosen->IsValid(&why)) return fail("bundle '" + chosen->name + "': " + why);
    return *chosen;
  } catch (const YAML::Exception& e) {
    return fail("is not a bundle file (line " + std::to_string(e.mark.line + 1) + ")");
  } catch (const std::runtime_error& e) {
    return fail(e.what());
  }
}

std::optional<Board> ReadBoardFile(const std::string& spec, std::string* error) {
  std::string path = spec, name;
  const auto hash = spec.find_last_of('#');
  if (hash != std::string::npos && hash > spec.find_last_of('/') + 1) {
    const std::string before = spec.substr(0, hash);
    const std::string ext = LowerExtension(before);
    if (ext == ".yaml" || ext == ".yml") {
      path = before;
      name = spec.substr(hash + 1);
    }
  }
  const std::string ext = LowerExtension(path);
  std::string why;
  const bool sheet = ext == ".pdf" || ext == ".svg" || ext == ".png";
  if (ext == ".json" || sheet) {
    // A sheet file stands for the sidecar beside it.
    std::string sidecar = path;
    const auto text = sheet ? ReadSidecarOfSheet(path, "board sheet", &sidecar, error)
                            : ReadInputFile(path, "board file", kMaxJsonFileBytes, error);
    if (!text) return std::nullopt;
    path = sidecar;
    // A colour calibration sheet's sidecar names its schema near the top.
    if (text->find(std::string("\"") + kCalibSheetSchema + "\"") != std::string::npos) {
      const auto layout = ParseCalibSidecar(*text, &why);
      std::optional<Board> board = layout ? BoardFromCalibSheet(*layout, &why) : std::nullopt;
      if (!board && error) *error = "board file '" + path + "': " + why;
      return board;
    }
    if (text->find("\"chromatag-layout\"") == std::string::npos) {
      if (error)
        *error = "board file '" + path +
                 "' is neither a sheet's sidecar (schema chromatag-layout, from chromatag "
                 "generate) nor a calibration sheet's (chromatag-calib-sheet, from chromatag "
                 "calib-sheet)";
      return std::nullopt;
    }
    const auto slash = path.find_last_of('/');
    auto sheet =
        ParseSidecar(*text, slash == std::string::npos ? "" : path.substr(0, slash + 1), &why);
    if (sheet) sheet->sidecar_path = path;  // The board's name.
    std::optional<Board> board = sheet ? BoardFromSheet(*sheet, &why) : std::nullopt;
    if (!board && error) *error = "board file '" + path + "': " + why;
    return board;
  }
  if (ext != ".yaml" && ext != ".yml") {
    if (error) {
      *error = "board file '" + path +
               "' must be a sheet from chromatag generate or calib-sheet (.pdf, .svg, .png, with "
               "its sidecar beside it), its sidecar (.json) or a bundle YAML (.yaml, .yml)";
    }
    return std::nullopt;
  }
  const auto text = ReadInputFile(path, "board file", kMaxBundleFileBytes, error);
  if (!text) return std::nullopt;
  auto board = ParseBundleYaml(*text, name, &why);
  if (!board && error) *error = "board file '" + path + "' " + why;
  return board;
}

}  // namespace chromatag
