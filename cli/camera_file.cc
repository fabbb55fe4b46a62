#include "camera_file.h"

#include "chromatag/families/input_file.h"
#include "commands.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

namespace chromatag::cli {
namespace {

// Camera files are a few hundred bytes; anything far larger is something else.
constexpr std::uintmax_t kMaxCameraFileBytes = 1 << 20;

// Fills *camera from a row-major 3x3 matrix and distortion coefficients.
bool FromMatrix(const std::vector<double>& k, const std::vector<double>& d,
                CameraIntrinsics* camera, std::string* error) {
  if (k.size() != 9) {
    *error = "camera_matrix must have 9 numbers (3x3), not " + std::to_string(k.size());
    return false;
  }
  camera->fx = k[0];
  camera->fy = k[4];
  camera->cx = k[2];
  camera->cy = k[5];
  camera->distortion = d;  // CameraIntrinsics::IsValid checks the count.
  return true;
}

// A YAML number list: [a, b, ...] or {rows, cols, data: [...]} (OpenCV's
// !!opencv-matrix and ROS's layout alike).
std::vector<double> YamlNumbers(const YAML::Node& node) {
  const YAML::Node list = node.IsMap() ? node["data"] : node;
  std::vector<double> out;
  if (!list || !list.IsSequence()) throw YAML::Exception(YAML::Mark::null_mark(), "no number list");
  for (const YAML::Node& item : list) {
    if (item.IsSequence()) {  // [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]
      for (const YAML::Node& x : item) out.push_back(x.as<double>());
    } else {
      out.push_back(item.as<double>());
    }
  }
  return out;
}

bool FromYaml(const std::string& text, CameraIntrinsics* camera, std::string* error) {
  // OpenCV writes a "%YAML:1.0" line, which is not YAML 1.2's directive.
  std::string body = text;
  if (body.rfind("%YAML", 0) == 0) body = body.substr(std::min(body.find('\n'), body.size()));
  YAML::Node root;
  try {
    root = YAML::Load(body);
  } catch (const YAML::Exception& e) {
    *error = "is not valid YAML (line " + std::to_string(e.mark.line + 1) + ")";
    return false;
  }
  try {
    if (!root.IsMap()) {
      *error = "is YAML but not a camera file (no camera_matrix)";
      return false;
    }
    if (root["camera_matrix"]) {  // OpenCV or ROS.
      std::vector<double> d;
      if (root["distortion_coefficients"]) d = YamlNumbers(root["distortion_coefficients"]);
      if (root["distortion_model"]) {
        const std::string model = root["distortion_model"].as<std::string>();
        if (model != "plumb_bob" && model != "rational_polynomial") {
          *error = "distortion_model '" + model +
                   "' is not supported (plumb_bob or rational_polynomial, as OpenCV's)";
          return false;
        }
      }
      return FromMatrix(YamlNumbers(root["camera_matrix"]), d, camera, error);
    }
    // Kalibr: the first camera of a camchain, or a single camera's block.
    YAML::Node cam = root["cam0"] ? root["cam0"] : root;
    if (cam["intrinsics"]) {
      const std::vector<double> i = YamlNumbers(cam["intrinsics"]);
      if (i.size() != 4) {
        *error = "intrinsics must be [fu, fv, pu, pv]";
        return false;
      }
      const std::string model =
          cam["distortion_model"] ? cam["distortion_model"].as<std::string>() : "none";
      std::vector<double> d;
      if (model == "radtan") {
        d = YamlNumbers(cam["distortion_coeffs"]);
      } else if (model != "none") {
        *error = "distortion_model '" + model + "' is not supported (radtan or none)";
        return false;
      }
      return FromMatrix({i[0], 0, i[2], 0, i[1], i[3], 0, 0, 1}, d, camera, error);
    }
  } catch (const YAML::Exception&) {
    *error = "has a camera_matrix or distortion that is not a list of numbers";
    return false;
  }
  *error = "names no camera_matrix (OpenCV, ROS camera_info) nor intrinsics (Kalibr)";
  return false;
}

bool FromJson(const std::string& text, CameraIntrinsics* camera, std::string* error) {
  try {
    const nlohmann::json root = nlohmann::json::parse(text);
    if (!root.is_object() || !root.contains("camera_matrix")) {
      *error = "names no camera_matrix";
      return false;
    }
    auto numbers = [](const nlohmann::json& node) {
      const nlohmann::json& list = node.is_object() ? node.at("data") : node;
      std::vector<double> out;
      for (const auto& x : list) {
        if (x.is_array()) {
          for (const auto& y : x) out.push_back(y.get<double>());
        } else {
          out.push_back(x.get<double>());
        }
      }
      return out;
    };
    std::vector<double> d;
    if (root.contains("distortion_coefficients")) d = numbers(root["distortion_coefficients"]);
    return FromMatrix(numbers(root["camera_matrix"]), d, camera, error);
  } catch (const nlohmann::json::parse_error&) {
    *error = "is not valid JSON";
  } catch (const nlohmann::json::exception&) {
    *error = "has a camera_matrix or distortion that is not a list of numbers";
  }
  return false;
}

// The text between <tag ...> and </tag> inside `text`; nullopt if either is missing.
std::optional<std::string> Element(const std::string& text, const std::string& tag) {
  size_t open = text.find("<" + tag);
  while (open != std::string::npos) {
    const char next = open + tag.size() + 1 < text.size() ? text[open + tag.size() + 1] : '\0';
    if (next == '>' || next == ' ' || next == '\t' || next == '\n' || next == '\r') break;
    open = text.find("<" + tag, open + 1);
  }
  if (open == std::string::npos) return std::nullopt;
  const size_t body = text.find('>', open);
  const size_t close = text.find("</" + tag + ">", body);
  if (body == std::string::npos || close == std::string::npos) return std::nullopt;
  return text.substr(body + 1, close - body - 1);
}

// Numbers separated by white space; nullopt on anything else.
std::optional<std::vector<double>> Numbers(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  for (std::string word; in >> word;) {
    char* end = nullptr;
    const double value = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0') return std::nullopt;
    out.push_back(value);
  }
  return out;
}

// OpenCV's XML layout, read here for the two matrices it needs:
// cv::FileStorage crashed on a truncated file (issue 12).
bool FromXml(const std::string& text, CameraIntrinsics* camera, std::string* error) {
  const auto storage = Element(text, "opencv_storage");
  if (!storage) {
    *error = "is not OpenCV XML (no complete <opencv_storage> element)";
    return false;
  }
  const auto matrix = Element(*storage, "camera_matrix");
  const auto k = matrix ? Element(*matrix, "data") : std::nullopt;
  const auto k_numbers = k ? Numbers(*k) : std::nullopt;
  if (!k_numbers) {
    *error = "needs a camera_matrix with 9 numbers in its <data>";
    return false;
  }
  std::vector<double> d;
  if (const auto distortion = Element(*storage, "distortion_coefficients")) {
    const auto data = Element(*distortion, "data");
    const auto numbers = data ? Numbers(*data) : std::nullopt;
    if (!numbers) {
      *error = "has distortion_coefficients without numbers in their <data>";
      return false;
    }
    d = *numbers;
  }
  return FromMatrix(*k_numbers, d, camera, error);
}

}  // namespace

bool ParseCameraFile(const std::string& text, const std::string& extension,
                     CameraIntrinsics* camera, std::string* why) {
  const std::string ext = Lower(extension);
  bool ok = false;
  if (ext == ".json") {
    ok = FromJson(text, camera, why);
  } else if (ext == ".xml") {
    ok = FromXml(text, camera, why);
  } else if (ext == ".yaml" || ext == ".yml") {
    ok = FromYaml(text, camera, why);
  } else {
    *why = "must be .yaml/.yml (OpenCV, ROS camera_info, Kalibr), .json or .xml (OpenCV)";
    return false;
  }
  return ok && camera->IsValid(why);
}

bool LoadCameraFile(const std::string& path, CameraIntrinsics* camera, std::string* error) {
  const auto text = ReadInputFile(path, "camera file", kMaxCameraFileBytes, error);
  if (!text) return false;
  std::string why;
  if (!ParseCameraFile(*text, std::filesystem::path(path).extension().string(), camera, &why)) {
    *error = "camera file '" + path + "' " + why;
    return false;
  }
  return true;
}

}  // namespace chromatag::cli
