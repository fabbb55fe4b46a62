// Detector config files (config.h).
#include "chromatag/detector/config.h"

#include "chromatag/families/input_file.h"

#include <algorithm>
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
    } else if (key == "step") {
      out->step = Integer(value, key);
    } else if (key == "row_step") {
      out->row_step = Integer(value, key);
    } else if (key == "adiff_thresh") {
      out->adiff_thresh = Number(value, key);
    } else if (key == "border_thresh") {
      out->border_thresh = Number(value, key);
    } else if (key == "border_run") {
      out->border_run = Integer(value, key);
    } else if (key == "max_green_a") {
      out->max_green_a = Number(value, key);
    } else if (key == "conv_thresh") {
      out->conv_thresh = Number(value, key);
    } else if (key == "max_hamming") {
      out->max_hamming = Integer(value, key);
    } else if (key == "min_decision_margin") {
      out->min_decision_margin = Number(value, key);
    } else if (key == "two_step_rises") {
      if (!value.is_boolean()) throw ConfigError{"\"two_step_rises\" must be true or false"};
      out->two_step_rises = value.get<bool>();
    } else if (key == "refine_corners") {
      if (!value.is_boolean()) throw ConfigError{"\"refine_corners\" must be true or false"};
      out->refine_corners = value.get<bool>();
    } else {
      throw ConfigError{"unknown option \"" + key +
                        "\" (allowed: families, step, row_step, adiff_thresh, border_thresh, "
                        "border_run, two_step_rises, max_green_a, conv_thresh, max_hamming, "
                        "min_decision_margin, refine_corners)"};
    }
  }
}

}  // namespace

std::string DetectorConfigToJson(const DetectorOptions& options,
                                 const std::vector<std::string>& fields,
                                 const std::string& provenance_json) {
  const Json all = {{"families", options.families},
                    {"step", options.step},
                    {"row_step", options.row_step},
                    {"adiff_thresh", options.adiff_thresh},
                    {"border_thresh", options.border_thresh},
                    {"border_run", options.border_run},
                    {"two_step_rises", options.two_step_rises},
                    {"max_green_a", options.max_green_a},
                    {"conv_thresh", options.conv_thresh},
                    {"max_hamming", options.max_hamming},
                    {"min_decision_margin", options.min_decision_margin},
                    {"refine_corners", options.refine_corners}};
  Json chosen = Json::object();
  for (const auto& [key, value] : all.items()) {
    if (fields.empty() || std::find(fields.begin(), fields.end(), key) != fields.end())
      chosen[key] = value;
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
    if (!root.contains("schema_version") || root["schema_version"] != 1)
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
