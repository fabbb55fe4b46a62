// Detector config files (config.h).
#include "chromatag/detector/config.h"

#include "chromatag/base/input_file.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace chromatag {
namespace {

using Json = nlohmann::ordered_json;

struct ConfigError {
  std::string message;
};

double Number(const Json& value, const std::string& key) {
  if (!value.is_number()) throw ConfigError{"\"" + key + "\" must be a number"};
  return value.get<double>();
}

int Integer(const Json& value, const std::string& key) {
  if (!value.is_number_integer()) throw ConfigError{"\"" + key + "\" must be an integer"};
  // Range first: 4294967300 would wrap to 4 in the cast.
  const bool fits = value.is_number_unsigned()
                        ? value.get<uint64_t>() <= static_cast<uint64_t>(INT_MAX)
                        : value.get<int64_t>() >= INT_MIN && value.get<int64_t>() <= INT_MAX;
  if (!fits) throw ConfigError{"\"" + key + "\" is out of range"};
  return value.get<int>();
}

// Three numbers, as [r, g, b].
std::array<double, 3> Triple(const Json& value, const std::string& key) {
  if (!value.is_array() || value.size() != 3)
    throw ConfigError{"\"" + key + "\" must be a list of three numbers, [r, g, b]"};
  std::array<double, 3> out;
  for (size_t i = 0; i < 3; ++i) out[i] = Number(value[i], key);
  return out;
}

// The options a config file names, in the order it is written: the one
// table that reading, writing and the list of allowed names share (Python's
// keyword arguments go through it too). Each has one of the four kinds.
struct Field {
  const char* name;
  int DetectorOptions::*integer;
  double DetectorOptions::*number;
  bool DetectorOptions::*flag;
  std::array<double, 3> DetectorOptions::*triple;
};

constexpr Field Int(const char* name, int DetectorOptions::*member) {
  return {name, member, nullptr, nullptr, nullptr};
}
constexpr Field Num(const char* name, double DetectorOptions::*member) {
  return {name, nullptr, member, nullptr, nullptr};
}
constexpr Field Flag(const char* name, bool DetectorOptions::*member) {
  return {name, nullptr, nullptr, member, nullptr};
}
constexpr Field Gains(const char* name, std::array<double, 3> DetectorOptions::*member) {
  return {name, nullptr, nullptr, nullptr, member};
}

// "families" comes first and is read apart (a list of names).
constexpr Field kFields[] = {
    Int("step", &DetectorOptions::step),
    Int("row_step", &DetectorOptions::row_step),
    Num("adiff_thresh", &DetectorOptions::adiff_thresh),
    Num("border_thresh", &DetectorOptions::border_thresh),
    Int("border_run", &DetectorOptions::border_run),
    Flag("two_step_rises", &DetectorOptions::two_step_rises),
    Flag("cast_seeds", &DetectorOptions::cast_seeds),
    Num("max_green_a", &DetectorOptions::max_green_a),
    Num("conv_thresh", &DetectorOptions::conv_thresh),
    Int("max_hamming", &DetectorOptions::max_hamming),
    Num("min_decision_margin", &DetectorOptions::min_decision_margin),
    Gains("white_balance", &DetectorOptions::white_balance),
};

std::string AllowedNames() {
  std::string out;
  for (const std::string& name : DetectorConfigFieldNames())
    out += (out.empty() ? "" : ", ") + name;
  return out;
}

void Apply(const Json& options, DetectorOptions* out) {
  if (!options.is_object()) throw ConfigError{"\"options\" must be an object"};
  for (const auto& [key, value] : options.items()) {
    if (key == "families") {
      if (!value.is_array()) throw ConfigError{"\"families\" must be a list, e.g. [\"16h5\"]"};
      out->families.clear();
      for (const Json& f : value) {
        if (!f.is_string()) throw ConfigError{"\"families\" must hold names: \"16h5\", \"36h11\""};
        out->families.push_back(f.get<std::string>());
      }
      continue;
    }
    if (key == "refine_corners") {
      // Files of this schema may hold it from when it was an option; the
      // sub-pixel corners are always on.
      if (value != Json(true))
        throw ConfigError{
            "\"refine_corners\": sub-pixel corners are always on; leave it out "
            "(or true)"};
      continue;
    }
    const Field* field = nullptr;
    for (const Field& f : kFields) field = key == f.name ? &f : field;
    if (!field)
      throw ConfigError{"unknown option \"" + key + "\" (allowed: " + AllowedNames() + ")"};
    if (field->integer) {
      out->*field->integer = Integer(value, key);
    } else if (field->number) {
      out->*field->number = Number(value, key);
    } else if (field->triple) {
      out->*field->triple = Triple(value, key);
    } else {
      if (!value.is_boolean()) throw ConfigError{"\"" + key + "\" must be true or false"};
      out->*field->flag = value.get<bool>();
    }
  }
}

}  // namespace

std::vector<std::string> DetectorConfigFieldNames() {
  std::vector<std::string> names = {"families"};
  for (const Field& field : kFields) names.push_back(field.name);
  return names;
}

std::string DetectorConfigToJson(const DetectorOptions& options,
                                 const std::vector<std::string>& fields,
                                 const std::string& provenance_json) {
  const auto wanted = [&](const std::string& name) {
    return fields.empty() || std::find(fields.begin(), fields.end(), name) != fields.end();
  };
  Json chosen = Json::object();
  if (wanted("families")) chosen["families"] = options.families;
  for (const Field& field : kFields) {
    if (!wanted(field.name)) continue;
    if (field.integer) {
      chosen[field.name] = options.*field.integer;
    } else if (field.number) {
      chosen[field.name] = options.*field.number;
    } else if (field.triple) {
      chosen[field.name] = options.*field.triple;
    } else {
      chosen[field.name] = options.*field.flag;
    }
  }
  Json root = {{"schema", kDetectorConfigSchema}, {"schema_version", 1}, {"options", chosen}};
  if (!provenance_json.empty()) root["calibration"] = Json::parse(provenance_json);
  return root.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

bool ParseDetectorConfig(const std::string& text, DetectorOptions* options, std::string* error) {
  DetectorOptions result = *options;
  if (JsonDeeperThan(text, kMaxJsonDepth)) {
    if (error) *error = "nests deeper than a detector config does";
    return false;
  }
  try {
    const Json root = Json::parse(text);
    if (!root.is_object()) throw ConfigError{"the file must hold a JSON object"};
    // The kind of file first: another tool's JSON (a sheet's sidecar, a
    // palette) is named as such, not as a detector config with odd members.
    if (!root.contains("schema") || root["schema"] != kDetectorConfigSchema) {
      const std::string kind = root.contains("schema") && root["schema"].is_string()
                                   ? "a \"" + root["schema"].get<std::string>() + "\" file"
                               : root.contains("format") && root["format"].is_string()
                                   ? "a \"" + root["format"].get<std::string>() + "\" file"
                                   : "a JSON file without \"schema\"";
      throw ConfigError{"this is " + kind + ", not a detector config (\"schema\": \"" +
                        kDetectorConfigSchema +
                        "\", as 'chromatag calibrate' writes detector.json)"};
    }
    for (const auto& [key, value] : root.items()) {
      if (key != "schema" && key != "schema_version" && key != "options" && key != "calibration")
        throw ConfigError{"unknown member \"" + key +
                          "\" (allowed: schema, schema_version, options, calibration)"};
    }
    if (!root.contains("schema_version"))
      throw ConfigError{"missing \"schema_version\" (this chromatag reads version 1)"};
    if (root["schema_version"] != 1)
      throw ConfigError{"unsupported schema_version (this chromatag reads version 1)"};
    if (!root.contains("options")) throw ConfigError{"missing \"options\""};
    Apply(root["options"], &result);
  } catch (const Json::exception& e) {
    if (error) *error = std::string("not valid JSON: ") + e.what();
    return false;
  } catch (const ConfigError& e) {
    if (error) *error = e.message;
    return false;
  }
  if (!result.IsValid(error)) return false;
  *options = result;
  return true;
}

bool LoadDetectorConfig(const std::string& path, DetectorOptions* options, std::string* error) {
  const auto text = ReadInputFile(path, "detector config", kMaxJsonFileBytes, error);
  if (!text) return false;
  std::string why;
  if (!ParseDetectorConfig(*text, options, &why)) {
    if (error) *error = "detector config '" + path + "': " + why;
    return false;
  }
  return true;
}

}  // namespace chromatag
