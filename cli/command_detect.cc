// `chromatag detect`: run the detector over images, folders and videos.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "chromatag/detector/config.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/draw.h"
#include "chromatag/families/family.h"
#include "chromatag/generator/units.h"
#include "commands.h"

namespace chromatag::cli {
namespace {

namespace fs = std::filesystem;

struct DetectOptions {
  std::string family = "16h5";
  bool json = false;
  std::string overlay_dir;
  std::string camera_file;
  std::string tag_size;
  std::string config;     // Detector config file, e.g. from chromatag calibrate.
  bool rejected = false;  // Report (JSON) and draw (overlay) rejected candidates.
  std::vector<std::string> inputs;
};

bool IsVideo(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  for (const char* v : {".avi", ".mp4", ".mkv", ".mov", ".webm", ".mpg", ".mpeg", ".m4v"})
    if (ext == v) return true;
  return false;
}

bool IsImage(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  for (const char* v : {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".pgm", ".webp"})
    if (ext == v) return true;
  return false;
}

// OpenCV's calibration file layout (camera_matrix, distortion_coefficients),
// YAML, XML or JSON.
bool LoadCamera(const std::string& path, CameraIntrinsics* camera, std::string* error) {
  cv::Mat k, d;
  try {
    cv::FileStorage file(path, cv::FileStorage::READ);
    if (!file.isOpened()) {
      *error = "cannot read camera file '" + path + "'";
      return false;
    }
    file["camera_matrix"] >> k;
    file["distortion_coefficients"] >> d;
  } catch (const cv::Exception&) {
    *error = "camera file '" + path + "' is not OpenCV YAML, XML or JSON";
    return false;
  }
  if (k.rows != 3 || k.cols != 3) {
    *error = "camera file '" + path + "' needs a 3x3 camera_matrix (and distortion_coefficients)";
    return false;
  }
  k.convertTo(k, CV_64F);
  camera->fx = k.at<double>(0, 0);
  camera->fy = k.at<double>(1, 1);
  camera->cx = k.at<double>(0, 2);
  camera->cy = k.at<double>(1, 2);
  camera->distortion.clear();
  if (!d.empty()) {
    d.convertTo(d, CV_64F);
    camera->distortion.assign(d.begin<double>(), d.end<double>());
  }
  return camera->IsValid(error);
}

class Runner {
 public:
  Runner(const DetectOptions& options, const Detector& detector)
      : options_(options), detector_(detector), progress_(isatty(STDERR_FILENO)) {}

  void Frame(const std::string& file, int frame_index, const cv::Mat& frame) {
    detector_.Detect(frame, PixelOrder::kBgr, &result_);
    if (options_.json) {
      nlohmann::json detections = nlohmann::json::array();
      for (const Detection& d : result_.detections) {
        nlohmann::json item = {{"family", d.family->name()},
                               {"id", d.id},
                               {"hamming", d.hamming},
                               {"margin", d.decision_margin},
                               {"corners", Points(d.corners)},
                               {"green_corners", Points(d.green_corners)},
                               {"red_corners", Points(d.red_corners)}};
        if (d.has_pose) {
          item["pose"] = {{"rvec", {d.pose.rvec[0], d.pose.rvec[1], d.pose.rvec[2]}},
                          {"tvec", {d.pose.tvec[0], d.pose.tvec[1], d.pose.tvec[2]}},
                          {"rms_error_px", d.pose.rms_error_px}};
        }
        detections.push_back(item);
      }
      nlohmann::json line = {{"file", file},
                             {"frame", frame_index},
                             {"width", frame.cols},
                             {"height", frame.rows},
                             {"time_us", result_.summary.total_time_us},
                             {"detections", detections}};
      if (options_.rejected) line["rejected"] = Rejected(result_.rejected);
      std::cout << line.dump() << "\n";
    } else {
      for (const Detection& d : result_.detections) {
        char line[256];
        std::snprintf(line, sizeof line, "%-30s %6d  %-6s %4d  %d  %6.1f  (%.1f, %.1f)",
                      file.c_str(), frame_index, d.family->name().c_str(), d.id, d.hamming,
                      d.decision_margin, d.corners[0].x, d.corners[0].y);
        std::cout << line;
        if (d.has_pose)
          std::cout << "  t = (" << d.pose.tvec[0] << ", " << d.pose.tvec[1] << ", "
                    << d.pose.tvec[2] << ") m";
        std::cout << "\n";
      }
      if (result_.detections.empty())
        std::cout << file << " frame " << frame_index << ": no tags\n";
    }
    if (!options_.overlay_dir.empty()) WriteOverlay(file, frame_index, frame);
  }

  void Progress(const std::string& what, size_t done, size_t total) {
    if (!progress_) return;
    const int width = 30;
    const int filled = total ? static_cast<int>(width * done / total) : width;
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu", what.c_str(), std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), done, total);
    if (done == total) std::fprintf(stderr, "\n");
  }

  bool failed = false;

 private:
  static nlohmann::json Points(const std::array<cv::Point2d, 4>& points) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& p : points) out.push_back({p.x, p.y});
    return out;
  }

  static nlohmann::json Rejected(const std::vector<RejectedCandidate>& rejected) {
    nlohmann::json out = nlohmann::json::array();
    for (const RejectedCandidate& r : rejected) {
      nlohmann::json outline = nlohmann::json::array();
      for (const auto& p : r.outline) outline.push_back({p.x, p.y});
      nlohmann::json record = {{"stage", StageName(r.stage)},
                               {"reason", RejectReasonName(r.reason)},
                               {"seed", {r.seed.x, r.seed.y}},
                               {"centre", {r.centre.x, r.centre.y}},
                               {"outline", outline}};
      // The second path's own reason, when it tried the candidate too.
      if (r.grown) record["grow_reason"] = RejectReasonName(r.grow_reason);
      out.push_back(std::move(record));
    }
    return out;
  }

  void WriteOverlay(const std::string& file, int frame_index, const cv::Mat& frame) {
    cv::Mat canvas = frame.clone();
    if (options_.rejected) DrawRejected(result_.rejected, &canvas);
    DrawDetections(result_.detections,
                   detector_.options().camera ? &*detector_.options().camera : nullptr,
                   detector_.options().tag_size, &canvas);
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, "_%06d.png", frame_index);
    const fs::path out = fs::path(options_.overlay_dir) / (fs::path(file).stem().string() + suffix);
    if (!cv::imwrite(out.string(), canvas)) {
      std::cerr << "chromatag detect: cannot write overlay '" << out.string() << "'\n";
      failed = true;
    }
  }

  const DetectOptions& options_;
  const Detector& detector_;
  bool progress_;
  DetectionResult result_;
};

void RunImage(const fs::path& path, Runner* runner) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (image.empty()) {
    std::cerr << "chromatag detect: cannot read image '" << path.string() << "', skipped\n";
    runner->failed = true;
    return;
  }
  runner->Frame(path.string(), 0, image);
}

void RunVideo(const fs::path& path, Runner* runner) {
  cv::VideoCapture video(path.string());
  if (!video.isOpened()) {
    std::cerr << "chromatag detect: cannot open video '" << path.string() << "', skipped\n";
    runner->failed = true;
    return;
  }
  const auto total = static_cast<size_t>(std::max(0.0, video.get(cv::CAP_PROP_FRAME_COUNT)));
  cv::Mat frame;
  int index = 0;
  while (video.read(frame)) {
    runner->Frame(path.string(), index++, frame);
    runner->Progress(path.filename().string(), std::min<size_t>(index, total), total);
  }
  if (index == 0) {
    std::cerr << "chromatag detect: no frames in video '" << path.string() << "', skipped\n";
    runner->failed = true;
  }
}

int RunDetect(const DetectOptions& options) {
  DetectorOptions detector_options;
  detector_options.families =
      options.family == "all" ? TagFamily::Names() : std::vector<std::string>{options.family};
  detector_options.report_rejected = options.rejected;
  std::string error;
  if (!options.config.empty() && !LoadDetectorConfig(options.config, &detector_options, &error)) {
    std::cerr << "chromatag detect: " << error << "\n";
    return kExitUsage;
  }
  if (!options.camera_file.empty()) {
    CameraIntrinsics camera;
    if (!LoadCamera(options.camera_file, &camera, &error)) {
      std::cerr << "chromatag detect: " << error << "\n";
      return kExitUsage;
    }
    detector_options.camera = camera;
  }
  if (!options.tag_size.empty()) {
    const auto length = ParseLength(options.tag_size, &error);
    if (!length) {
      std::cerr << "chromatag detect: --tag-size: " << error << "\n";
      return kExitUsage;
    }
    detector_options.tag_size = length->mm / 1000.0;
  }
  if (detector_options.camera.has_value() != (detector_options.tag_size > 0)) {
    std::cerr << "chromatag detect: pose needs both --camera FILE and --tag-size LENGTH\n";
    return kExitUsage;
  }
  if (!options.overlay_dir.empty()) {
    std::error_code ec;
    fs::create_directories(options.overlay_dir, ec);
    if (ec) {
      std::cerr << "chromatag detect: cannot create overlay folder '" << options.overlay_dir
                << "': " << ec.message() << "\n";
      return kExitUsage;
    }
  }
  auto detector = Detector::Create(detector_options, &error);
  if (!detector) {
    std::cerr << "chromatag detect: " << error << "\n";
    return kExitUsage;
  }
  Runner runner(options, *detector);
  if (!options.json)
    std::cout << "file                            frame  family   id  h  margin  corner 0\n";
  for (const std::string& input : options.inputs) {
    const fs::path path(input);
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
      std::vector<fs::path> files;
      for (const auto& entry : fs::directory_iterator(path, ec)) {
        if (entry.is_regular_file() && (IsImage(entry.path()) || IsVideo(entry.path())))
          files.push_back(entry.path());
      }
      std::sort(files.begin(), files.end());
      for (size_t i = 0; i < files.size(); ++i) {
        IsVideo(files[i]) ? RunVideo(files[i], &runner) : RunImage(files[i], &runner);
        runner.Progress(path.string(), i + 1, files.size());
      }
    } else if (!fs::exists(path, ec)) {
      std::cerr << "chromatag detect: no such file or folder '" << input << "', skipped\n";
      runner.failed = true;
    } else if (IsVideo(path)) {
      RunVideo(path, &runner);
    } else {
      RunImage(path, &runner);
    }
  }
  return runner.failed ? kExitFailure : kExitOk;
}

}  // namespace

void RegisterDetect(CLI::App& app, Action* action) {
  auto options = std::make_shared<DetectOptions>();
  CLI::App* command =
      app.add_subcommand("detect", "Detect ChromaTags in images, folders of images and videos");
  command->add_option("--family", options->family, "Tag family: 16h5, 36h11 or all")
      ->check(CLI::IsMember({"16h5", "36h11", "all"}));
  command->add_flag("--json", options->json, "One JSON object per frame per line");
  command->add_option("--overlay", options->overlay_dir,
                      "Write each frame with the detections drawn into this folder");
  command->add_option("--camera", options->camera_file,
                      "Camera intrinsics (OpenCV YAML/XML/JSON: camera_matrix, "
                      "distortion_coefficients), for pose");
  command->add_option("--tag-size", options->tag_size,
                      "Side of the black square, e.g. 40mm, for pose");
  command->add_option("--config", options->config,
                      "Detector config JSON (thresholds from 'chromatag calibrate')");
  command->add_flag("--rejected", options->rejected,
                    "Also report the rejected candidates (JSON: \"rejected\") and draw them on "
                    "the overlays, coloured by the stage that rejected them");
  command->add_option("INPUT", options->inputs, "Image files, folders or video files")->required();
  command->callback([options, action] { *action = [options] { return RunDetect(*options); }; });
}

}  // namespace chromatag::cli
