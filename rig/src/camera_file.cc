#include "chromatag/rig/camera_file.h"

#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "bounded_yaml.h"
#include "chromatag/base/input_file.h"

namespace chromatag {
namespace {

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// Camera files are a few hundred bytes; anything far larger is something else.
constexpr std::uintmax_t kMaxCameraFileBytes = 1 << 20;

// Fills *camera from a row-major 3x3 matrix and distortion coefficients.
bool FromMatrix(const std::vector<double>& k, const std::vector<double>& d,
                CameraIntrinsics* camera, std::string* error) {
  if (k.size() != 9) {
    *error = "camera_matrix must have 9 numbers (3x3), not " + std::to_string(k.size());
    return false;
  }
  double matrix[9];
  std::copy(k.begin(), k.end(), matrix);
  if (!IntrinsicsFromMatrix(matrix, camera, error)) return false;
  camera->distortion = d;  // CameraIntrinsics::IsValid checks the count.
  return true;
}

// OpenCV's and ROS's names of a distortion model: false (and *error) for
// one this toolkit does not handle.
bool ModelFromName(const std::string& name, LensModel* model, std::string* error) {
  if (name == "fisheye" || name == "equidistant") {
    *model = LensModel::kFisheye;
    return true;
  }
  if (name == "plumb_bob" || name == "rational_polynomial" || name == "pinhole") {
    *model = LensModel::kPinhole;
    return true;
  }
  *error = "distortion_model '" + name +
           "' is not supported (plumb_bob, rational_polynomial, or fisheye / equidistant for "
           "OpenCV's fisheye model)";
  return false;
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
    root = internal::LoadBoundedYaml(body);
  } catch (const YAML::Exception& e) {
    *error = "is not valid YAML (" + internal::YamlErrorAt(e) + ")";
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
      if (root["distortion_model"] &&
          !ModelFromName(root["distortion_model"].as<std::string>(), &camera->model, error))
        return false;
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
      if (cam["camera_model"] && cam["camera_model"].as<std::string>() != "pinhole") {
        *error = "camera_model '" + cam["camera_model"].as<std::string>() +
                 "' is not supported (pinhole, with radtan or equidistant distortion)";
        return false;
      }
      const std::string model =
          cam["distortion_model"] ? cam["distortion_model"].as<std::string>() : "none";
      std::vector<double> d;
      if (model == "radtan" || model == "equidistant") {
        d = YamlNumbers(cam["distortion_coeffs"]);
        if (model == "equidistant") camera->model = LensModel::kFisheye;
      } else if (model != "none") {
        *error = "distortion_model '" + model + "' is not supported (radtan, equidistant or none)";
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
    if (root.contains("distortion_model") &&
        !ModelFromName(root["distortion_model"].get<std::string>(), &camera->model, error))
      return false;
    return FromMatrix(numbers(root["camera_matrix"]), d, camera, error);
  } catch (const nlohmann::json::parse_error&) {
    *error = "is not valid JSON";
  } catch (const nlohmann::json::exception&) {
    *error = "has a camera_matrix or distortion that is not a list of numbers";
  }
  return false;
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

// An OpenCV XML file parsed: the document and its <opencv_storage> root.
struct OpenCvXml {
  tinyxml2::XMLDocument doc;
  const tinyxml2::XMLElement* storage = nullptr;
};

// Parses `text` as OpenCV's XML layout (cv::FileStorage crashed on a
// truncated file; tinyxml2 reads comments, CDATA and entities as XML does,
// and no DTD). False (and *error) if it is not.
bool ParseOpenCvXml(const std::string& text, OpenCvXml* xml, std::string* error) {
  if (xml->doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    *error =
        "is not OpenCV XML (invalid XML at line " + std::to_string(xml->doc.ErrorLineNum()) + ")";
    return false;
  }
  xml->storage = xml->doc.RootElement();
  if (!xml->storage || std::string(xml->storage->Name()) != "opencv_storage") {
    *error = "is not OpenCV XML (its root element is not <opencv_storage>)";
    return false;
  }
  return true;
}

// The text of `parent`'s one child element `name` ("" if it has none);
// nullopt if there is none, and also (with *error) if there are two.
std::optional<std::string> ChildText(const tinyxml2::XMLElement* parent, const char* name,
                                     std::string* error) {
  const tinyxml2::XMLElement* child = parent->FirstChildElement(name);
  if (!child) return std::nullopt;
  if (child->NextSiblingElement(name)) {
    *error = std::string("has two <") + name + "> elements";
    return std::nullopt;
  }
  const char* text = child->GetText();
  return std::string(text ? text : "");
}

// OpenCV's XML layout, read for the two matrices it needs.
bool FromXml(const std::string& text, CameraIntrinsics* camera, std::string* error) {
  OpenCvXml xml;
  if (!ParseOpenCvXml(text, &xml, error)) return false;
  std::string twice;  // Set when an element comes twice.
  const auto matrix_numbers = [&](const char* name) -> std::optional<std::vector<double>> {
    const tinyxml2::XMLElement* matrix = xml.storage->FirstChildElement(name);
    if (!matrix) return std::nullopt;
    if (matrix->NextSiblingElement(name)) {
      twice = std::string("has two <") + name + "> elements";
      return std::nullopt;
    }
    const auto data = ChildText(matrix, "data", &twice);
    return data ? Numbers(*data) : std::nullopt;
  };
  const auto k_numbers = matrix_numbers("camera_matrix");
  if (!k_numbers) {
    *error = twice.empty() ? "needs a camera_matrix with 9 numbers in its <data>" : twice;
    return false;
  }
  std::vector<double> d;
  if (xml.storage->FirstChildElement("distortion_coefficients")) {
    const auto numbers = matrix_numbers("distortion_coefficients");
    if (!numbers) {
      *error =
          twice.empty() ? "has distortion_coefficients without numbers in their <data>" : twice;
      return false;
    }
    d = *numbers;
  }
  const auto model = ChildText(xml.storage, "distortion_model", &twice);
  if (!twice.empty()) {
    *error = twice;
    return false;
  }
  if (model) {
    std::string name = *model;
    name.erase(0, name.find_first_not_of(" \t\r\n\""));
    name.erase(name.find_last_not_of(" \t\r\n\"") + 1);
    if (!ModelFromName(name, &camera->model, error)) return false;
  }
  return FromMatrix(*k_numbers, d, camera, error);
}

// The image size a camera file records, (0, 0) when it records none or one
// that is not two positive integers: image_width and image_height (OpenCV,
// ROS), or resolution [w, h] (Kalibr).
cv::Size RecordedImageSize(const std::string& text, const std::string& ext) {
  const auto valid = [](long long w, long long h) {
    return w > 0 && h > 0 && w <= (1 << 20) && h <= (1 << 20)
               ? cv::Size(static_cast<int>(w), static_cast<int>(h))
               : cv::Size();
  };
  try {
    if (ext == ".json") {
      const nlohmann::json root = nlohmann::json::parse(text);
      return valid(root.at("image_width").get<long long>(),
                   root.at("image_height").get<long long>());
    }
    if (ext == ".xml") {
      OpenCvXml xml;
      std::string ignored;
      if (!ParseOpenCvXml(text, &xml, &ignored)) return {};
      const auto w = ChildText(xml.storage, "image_width", &ignored),
                 h = ChildText(xml.storage, "image_height", &ignored);
      const auto wn = w ? Numbers(*w) : std::nullopt, hn = h ? Numbers(*h) : std::nullopt;
      if (!wn || !hn || wn->size() != 1 || hn->size() != 1) return {};
      if ((*wn)[0] != std::floor((*wn)[0]) || (*hn)[0] != std::floor((*hn)[0])) return {};
      return valid(static_cast<long long>((*wn)[0]), static_cast<long long>((*hn)[0]));
    }
    std::string body = text;
    if (body.rfind("%YAML", 0) == 0) body = body.substr(std::min(body.find('\n'), body.size()));
    const YAML::Node root = internal::LoadBoundedYaml(body);
    if (root["image_width"] && root["image_height"])
      return valid(root["image_width"].as<long long>(), root["image_height"].as<long long>());
    const YAML::Node cam = root["cam0"] ? root["cam0"] : root;
    if (cam["resolution"] && cam["resolution"].IsSequence() && cam["resolution"].size() == 2)
      return valid(cam["resolution"][0].as<long long>(), cam["resolution"][1].as<long long>());
  } catch (const std::exception&) {
    // Not recorded in a form read here: no size.
  }
  return {};
}

}  // namespace

bool ParseCameraFile(const std::string& text, const std::string& extension,
                     CameraIntrinsics* camera, std::string* why, CameraFileInfo* info) {
  const std::string ext = Lower(extension);
  *camera = CameraIntrinsics();  // A pinhole camera unless the file says otherwise.
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
  if (!ok || !camera->IsValid(why)) return false;
  if (info) {
    *info = CameraFileInfo();
    info->image_size = RecordedImageSize(text, ext);
  }
  return true;
}

bool LoadCameraFile(const std::string& path, CameraIntrinsics* camera, std::string* error,
                    CameraFileInfo* info) {
  const auto text = ReadInputFile(path, "camera file", kMaxCameraFileBytes, error);
  if (!text) return false;
  std::string why;
  if (!ParseCameraFile(*text, std::filesystem::path(path).extension().string(), camera, &why,
                       info)) {
    *error = "camera file '" + path + "' " + why;
    return false;
  }
  return true;
}

const char* CameraFileFormatName(CameraFileFormat format) {
  switch (format) {
    case CameraFileFormat::kOpenCv:
      return "opencv";
    case CameraFileFormat::kRos:
      return "ros";
    case CameraFileFormat::kKalibr:
      return "kalibr";
  }
  return "?";
}

namespace {

// A number as YAML and JSON read it back: 17 significant digits, no locale.
std::string Number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string List(const std::vector<double>& values) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + Number(values[i]);
  return out + "]";
}

// {rows, cols, data} as ROS writes its matrices.
std::string RosMatrix(const char* name, int rows, int cols, const std::vector<double>& data) {
  return std::string(name) + ":\n  rows: " + std::to_string(rows) +
         "\n  cols: " + std::to_string(cols) + "\n  data: " + List(data) + "\n";
}

}  // namespace

std::string CameraFileText(const CameraIntrinsics& camera, const CameraFileInfo& info,
                           CameraFileFormat format, std::string* error) {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return std::string();
  };
  if (!camera.IsValid(error)) return {};
  // Written into YAML unquoted, and into Kalibr's topic name.
  if (info.camera_name.empty() ||
      !std::all_of(info.camera_name.begin(), info.camera_name.end(),
                   [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }))
    return fail("camera name '" + info.camera_name + "': letters, digits and _ only");
  const bool fisheye = camera.model == LensModel::kFisheye;
  std::vector<double> d = camera.distortion;
  const std::vector<double> k = {camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1};
  std::string out;
  switch (format) {
    case CameraFileFormat::kOpenCv: {
      // OpenCV's own writer, so that cv::FileStorage reads it back as it
      // reads the output of OpenCV's calibration samples.
      cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
      fs << "image_width" << info.image_size.width;
      fs << "image_height" << info.image_size.height;
      fs << "camera_name" << info.camera_name;
      fs << "distortion_model"
         << (fisheye         ? "fisheye"
             : d.size() == 8 ? "rational_polynomial"
                             : "plumb_bob");
      fs << "camera_matrix" << cv::Mat(cv::Matx33d(k.data()));
      if (d.empty()) d.assign(fisheye ? 4 : 5, 0.0);
      fs << "distortion_coefficients" << cv::Mat(d, true).reshape(1, 1);
      if (info.rms_px >= 0) fs << "avg_reprojection_error" << info.rms_px;
      out = fs.releaseAndGetString();
      if (!out.empty() && out.back() != '\n') out += '\n';
      break;
    }
    case CameraFileFormat::kRos: {
      // ROS plumb_bob is k1, k2, p1, p2, k3; eight coefficients are
      // rational_polynomial; equidistant is cv::fisheye's k1-k4.
      const char* model = fisheye         ? "equidistant"
                          : d.size() == 8 ? "rational_polynomial"
                                          : "plumb_bob";
      if (!fisheye && d.size() < 5) d.resize(5, 0.0);
      out = "image_width: " + std::to_string(info.image_size.width) +
            "\nimage_height: " + std::to_string(info.image_size.height) +
            "\ncamera_name: " + info.camera_name + "\n" + RosMatrix("camera_matrix", 3, 3, k) +
            "distortion_model: " + model + "\n" +
            RosMatrix("distortion_coefficients", 1, static_cast<int>(d.size()), d) +
            RosMatrix("rectification_matrix", 3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1}) +
            RosMatrix("projection_matrix", 3, 4,
                      {camera.fx, 0, camera.cx, 0, 0, camera.fy, camera.cy, 0, 0, 0, 1, 0});
      break;
    }
    case CameraFileFormat::kKalibr: {
      // Kalibr's radtan has k1, k2, r1, r2 only.
      if (!fisheye && d.size() > 4) {
        for (size_t i = 4; i < d.size(); ++i) {
          if (d[i] != 0.0)
            return fail(
                "Kalibr's radtan model has no k3 to k6: calibrate with k3 fixed at 0 for a "
                "Kalibr camchain");
        }
        d.resize(4);
      }
      if (d.empty()) d.assign(4, 0.0);
      out = "cam0:\n  camera_model: pinhole\n  intrinsics: " +
            List({camera.fx, camera.fy, camera.cx, camera.cy}) +
            "\n  distortion_model: " + (fisheye ? "equidistant" : "radtan") +
            "\n  distortion_coeffs: " + List(d) + "\n  resolution: [" +
            std::to_string(info.image_size.width) + ", " + std::to_string(info.image_size.height) +
            "]\n  rostopic: /" + info.camera_name + "/image_raw\n";
      break;
    }
  }
  return out;
}

}  // namespace chromatag
