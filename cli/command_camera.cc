// chromatag calibrate-camera: intrinsics from views of a ChromaTag board.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <opencv2/videoio.hpp>
#include <optional>

#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/calib/camera_calibration.h"
#include "chromatag/calib/camera_report.h"
#include "chromatag/calib/view_selection.h"
#include "chromatag/detector/config.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/rig/board_file.h"
#include "chromatag/rig/camera_file.h"
#include "commands.h"
#include "progress.h"
#include "sources.h"

namespace chromatag::cli {
namespace {

namespace fs = std::filesystem;

struct CameraCalibOptions {
  std::vector<std::string> inputs;
  std::vector<int> camera_indices;
  std::string board_file;
  std::string output;
  std::string format = "opencv";
  std::string model = "pinhole";
  bool k3 = false;
  int max_views = 40;
  std::vector<std::string> reports;
  std::string config;
  std::string camera_name = "camera";
  bool write_uncertain = false;
  std::string distance;  // --distance: a length; empty for the views' median.
};

// Ctrl-C ends the reading of a live camera and calibrates with the views
// kept so far; a second one ends the process.
std::atomic<bool> g_stop{false};

void OnInterrupt(int) {
  g_stop = true;
  std::signal(SIGINT, SIG_DFL);
}

// Reads the inputs, detects, and keeps the views to calibrate with.
class ViewCollector {
 public:
  ViewCollector(const Detector& detector, const Board& board, const ViewSelectionOptions& options)
      : detector_(detector), board_(board), selection_(options) {}

  // Messages for skipped inputs go to stderr.
  void Read(const std::vector<Source>& sources) {
    const size_t images =
        static_cast<size_t>(std::count_if(sources.begin(), sources.end(), [](const Source& s) {
          return s.kind == SourceKind::kImage;
        }));
    Progress progress("calibrate-camera", "images", images);
    size_t read = 0;
    for (const Source& source : sources) {
      if (g_stop) break;
      if (source.kind == SourceKind::kImage) {
        ReadFile(source.name);
        progress.Update(++read);
      } else {
        ReadVideo(source);
      }
    }
    progress.Finish();
  }

  // The views of the image size most of them have; the others are named
  // and skipped (one calibration is for one image size).
  std::vector<CalibrationView> Views(cv::Size* size) {
    std::map<std::pair<int, int>, int> count;
    for (const cv::Size& s : sizes_) ++count[{s.width, s.height}];
    std::pair<int, int> most{0, 0};
    for (const auto& [s, n] : count)
      if (n > count[most]) most = s;
    *size = cv::Size(most.first, most.second);
    std::vector<CalibrationView> kept;
    for (size_t i = 0; i < views_.size(); ++i) {
      if (sizes_[i] == *size) {
        kept.push_back(views_[i]);
      } else {
        Skip("'" + views_[i].name + "' is " + std::to_string(sizes_[i].width) + " x " +
             std::to_string(sizes_[i].height) + ", most views " + std::to_string(size->width) +
             " x " + std::to_string(size->height) + " (one calibration is for one image size)");
      }
    }
    return kept;
  }

  bool failed() const { return failed_; }

 private:
  void Skip(const std::string& message) {
    std::cerr << "calibrate-camera: " << message << ", skipped\n";
    failed_ = true;
  }

  void Add(const std::string& name, const std::vector<Detection>& detections, cv::Size size) {
    views_.push_back({name, detections});
    sizes_.push_back(size);
  }

  // Every image given is used: the user chose it.
  void ReadFile(const std::string& path) {
    std::string error;
    const cv::Mat frame = ReadImage(path, &error);
    if (frame.empty()) return Skip(error);
    DetectionResult result;
    detector_.Detect(frame, PixelOrder::kBgr, &result);
    Add(path, result.detections, frame.size());
  }

  // Frames of a video are chosen once all are seen; a live camera's as they
  // come, until the cap or Ctrl-C. One selector serves every video and
  // camera of the run, so the cap and the kept poses are the run's.
  void ReadVideo(const Source& source) {
    cv::VideoCapture capture;
    if (!OpenSource(source, kDefaultOpenTimeout, &capture))
      return Skip("cannot open '" + source.name + "'");
    VideoViews video;
    if (!ReadFrames(source, &capture, &video)) return;
    if (video.frames == 0) return Skip("no frames in '" + source.name + "'");
    if (!source.live()) KeepChosen(source, &video);
  }

  // A video's frames described as candidate views, or a live camera's kept
  // as they come.
  struct VideoViews {
    int frames = 0;
    cv::Size size;
    std::vector<ViewPose> poses;
    std::vector<CalibrationView> candidates;
    std::map<std::string, int> not_kept;  // Reason -> frames.
  };

  // False when the source is skipped (said why).
  bool ReadFrames(const Source& source, cv::VideoCapture* capture, VideoViews* video) {
    DetectionResult result;
    while (!g_stop) {
      cv::Mat frame;
      if (!capture->read(frame) || frame.empty()) break;
      if (frame.type() != CV_8UC3) {
        Skip("'" + source.name + "' gives frames that are not 8-bit colour");
        return false;
      }
      if (!selector_) {
        selector_.emplace(board_, frame.size(), selection_);
        selector_size_ = frame.size();
      }
      if (frame.size() != selector_size_) {
        Skip("'" + source.name + "' gives " + std::to_string(frame.cols) + " x " +
             std::to_string(frame.rows) + " frames, the first video " +
             std::to_string(selector_size_.width) + " x " + std::to_string(selector_size_.height));
        return false;
      }
      video->size = frame.size();
      detector_.Detect(frame, PixelOrder::kBgr, &result);
      const std::string name = source.name + " frame " + std::to_string(video->frames++);
      if (source.live()) {
        const ViewDecision decision = selector_->Offer(result.detections);
        if (decision.keep) {
          Add(name, result.detections, video->size);
          std::cerr << "calibrate-camera: kept " << name << " (" << selector_->kept() << " of "
                    << selection_.max_views << "): " << decision.why << "\n";
          if (selector_->full()) break;
        }
        continue;
      }
      ViewPose pose;
      std::string why;
      if (!selector_->Describe(result.detections, &pose, &why)) {
        ++video->not_kept[why.find("board tag") != std::string::npos ? "too few board tags" : why];
        continue;
      }
      video->poses.push_back(pose);
      video->candidates.push_back({name, result.detections});
    }
    return true;
  }

  // A video's views chosen from all its frames, and what was not kept.
  void KeepChosen(const Source& source, VideoViews* video) {
    std::vector<std::string> why;
    const std::vector<size_t> chosen = selector_->Choose(video->poses, &why);
    for (size_t i : chosen) {
      std::cerr << "calibrate-camera: kept " << video->candidates[i].name << ": " << why[i] << "\n";
      Add(video->candidates[i].name, video->candidates[i].detections, video->size);
    }
    for (size_t i = 0; i < why.size(); ++i) {
      if (std::find(chosen.begin(), chosen.end(), i) != chosen.end()) continue;
      ++video->not_kept[why[i].rfind("like a kept view", 0) == 0 ? "like a kept view" : why[i]];
    }
    std::string summary;
    for (const auto& [reason, count] : video->not_kept)
      summary += (summary.empty() ? "" : ", ") + std::to_string(count) + " " + reason;
    std::cerr << "calibrate-camera: " << source.name << ": " << video->frames << " frames, kept "
              << chosen.size() << (summary.empty() ? "" : "; not kept: " + summary) << "\n";
  }

  const Detector& detector_;
  const Board& board_;
  const ViewSelectionOptions selection_;
  std::optional<ViewSelector> selector_;
  cv::Size selector_size_;
  std::vector<CalibrationView> views_;
  std::vector<cv::Size> sizes_;
  bool failed_ = false;
};

void PrintResult(const CameraCalibration& c) {
  Print("view                                      tags  rms px\n");
  for (const CalibrationViewResult& v : c.views) {
    std::string name = v.name;
    if (name.size() > 40) name = "..." + name.substr(name.size() - 37);
    if (v.used) {
      Print("%-40s %6d  %6.3f", name.c_str(), v.tags, v.rms_px);
      for (size_t t = 0; t < v.tags_left_out.size(); ++t)
        Print("  left out ID %d: %s", v.tags_left_out[t], v.why_left_out[t].c_str());
      Print("\n");
    } else {
      Print("%-40s  left out: %s\n", name.c_str(), v.why_not.c_str());
    }
  }
  const std::vector<std::string> names = CalibrationParameterNames(c.camera);
  std::vector<double> values = {c.camera.fx, c.camera.fy, c.camera.cx, c.camera.cy};
  values.insert(values.end(), c.camera.distortion.begin(), c.camera.distortion.end());
  Print("\n%s model, %d x %d, %d corners, reprojection rms %.3f px\n",
        LensModelName(c.camera.model), c.image_size.width, c.image_size.height, c.corners_used,
        c.rms_px);
  for (size_t i = 0; i < names.size() && i < values.size(); ++i) {
    const double deviation = i < c.std_dev.size() ? c.std_dev[i] : 0.0;
    if (i >= 4 && deviation == 0.0 && values[i] == 0.0) {
      Print("  %-3s %12.6f (not fitted)\n", names[i].c_str(), values[i]);
    } else {
      Print(i < 4 ? "  %-3s %12.3f +- %.3f px\n" : "  %-3s %12.6f +- %.6f\n", names[i].c_str(),
            values[i], deviation);
    }
  }
  const ProjectionCheck& p = c.projection;
  Print("projection at %.3g m, central 80 %% of the image (median / worst):\n", p.distance);
  Print("  uncertainty       %.3f / %.3f px (limit %.1f)\n", p.uncertainty_median_px,
        p.uncertainty_worst_px, kMaxProjectionUncertaintyPx);
  if (p.cross_validation_px.empty()) {
    Print("  cross-validation  not measured (fewer than six views)\n");
  } else {
    Print("  cross-validation  %.3f / %.3f px (limit %.1f): two halves of the views fitted apart\n",
          p.cross_validation_median_px, p.cross_validation_worst_px, kMaxCrossValidationPx);
  }
  std::fflush(stdout);
  for (const std::string& w : c.doubts) std::cerr << "calibrate-camera: uncertain: " << w << "\n";
  for (const std::string& w : c.warnings) std::cerr << "calibrate-camera: warning: " << w << "\n";
}

// What the command line asks for, checked before a long run: the formats,
// names and limits, and that no output overwrites an input.
bool CheckArguments(const CameraCalibOptions& o, CameraFileFormat* format,
                    CameraCalibrationOptions* calibration_options, ViewSelectionOptions* selection,
                    std::string* error) {
  const auto fail = [&](const std::string& message) {
    *error = message;
    return false;
  };
  *format = o.format == "ros"      ? CameraFileFormat::kRos
            : o.format == "kalibr" ? CameraFileFormat::kKalibr
                                   : CameraFileFormat::kOpenCv;
  calibration_options->model = o.model == "fisheye" ? LensModel::kFisheye : LensModel::kPinhole;
  calibration_options->fit_k3 = o.k3;
  if (!calibration_options->IsValid(error)) return fail("--k3: " + *error);
  if (!o.distance.empty()) {
    const auto length = ParseLength(o.distance, error);
    if (!length || !(length->mm > 0))
      return fail("--distance: " + (length ? std::string("must be more than 0") : *error));
    calibration_options->working_distance = length->mm / 1000.0;
  }
  if (o.k3 && *format == CameraFileFormat::kKalibr)
    return fail("--k3 with --format kalibr: Kalibr's radtan model has no k3");
  const std::string ext = LowerExtension(o.output);
  if (ext != ".yaml" && ext != ".yml")
    return fail("-o '" + o.output + "': camera files are YAML (.yaml or .yml)");
  for (const std::string& report : o.reports) {
    const std::string e = LowerExtension(report);
    if (e != ".pdf" && e != ".png") return fail("--report '" + report + "': .pdf or .png");
  }
  if (o.camera_name.empty() ||
      !std::all_of(o.camera_name.begin(), o.camera_name.end(), [](char ch) {
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_';
      }))
    return fail("--camera-name '" + o.camera_name + "': letters, digits and _ only");
  for (int index : o.camera_indices) {
    if (index < 0) return fail("--camera-index " + std::to_string(index) + ": 0 or more");
  }
  selection->max_views = o.max_views;
  if (!selection->IsValid(error)) return fail("--max-views: " + *error);
  std::vector<std::string> outputs = {o.output};
  outputs.insert(outputs.end(), o.reports.begin(), o.reports.end());
  if (!CheckOutputTargets(outputs, error, /*try_create=*/true)) return false;
  std::vector<std::pair<std::string, std::string>> inputs = {{"--board", o.board_file}};
  if (!o.config.empty()) inputs.push_back({"--config", o.config});
  for (const std::string& input : o.inputs) inputs.push_back({"an input", input});
  return CheckOutputsAreNotInputs(outputs, inputs, error);
}

// A detector for the board's families, with --config's thresholds.
std::unique_ptr<Detector> BoardDetector(const Board& board, const std::string& config,
                                        std::string* error) {
  DetectorOptions detector_options;
  detector_options.families.clear();
  for (const BoardTag& tag : board.tags) {
    if (std::find(detector_options.families.begin(), detector_options.families.end(), tag.family) ==
        detector_options.families.end())
      detector_options.families.push_back(tag.family);
  }
  if (!config.empty()) {
    const std::vector<std::string> families = detector_options.families;
    if (!LoadDetectorConfig(config, &detector_options, error)) return nullptr;
    detector_options.families = families;  // The board's, whatever the config says.
  }
  return Detector::Create(detector_options, error);
}

// The camera file and the reports, all or nothing.
int WriteCalibration(const CameraCalibOptions& o, const CameraCalibration& calibration,
                     CameraFileFormat format) {
  std::string error;
  CameraFileInfo info;
  info.image_size = calibration.image_size;
  info.camera_name = o.camera_name;
  info.rms_px = calibration.rms_px;
  const std::string text = CameraFileText(calibration.camera, info, format, &error);
  if (text.empty()) return Fail("calibrate-camera", error, kExitFailure);
  std::vector<OutputFile> files = {{o.output, text}};
  const std::string title = fs::path(o.board_file).filename().string();
  for (const std::string& report : o.reports) {
    files.push_back({report, LowerExtension(report) == ".pdf"
                                 ? RenderCameraReportPdf(calibration, title)
                                 : RenderCameraReportPng(calibration, title)});
  }
  if (!WriteFilesAtomically(files, &error)) return Fail("calibrate-camera", error, kExitFailure);
  std::cerr << "calibrate-camera: wrote " << o.output;
  for (const std::string& report : o.reports) std::cerr << ", " << report;
  std::cerr << "\n";
  return kExitOk;
}

int RunCalibrateCamera(const CameraCalibOptions& o) {
  const auto fail = [](const std::string& message) { return Fail("calibrate-camera", message); };
  CameraFileFormat format;
  CameraCalibrationOptions calibration_options;
  ViewSelectionOptions selection;
  std::string error;
  if (!CheckArguments(o, &format, &calibration_options, &selection, &error)) return fail(error);
  const std::optional<Board> board = ReadBoardFile(o.board_file, &error);
  if (!board) return fail(error);
  if (!CheckCalibrationBoard(*board, calibration_options, &error))
    return fail("--board '" + o.board_file + "': " + error);
  const auto detector = BoardDetector(*board, o.config, &error);
  if (!detector) return fail(error);
  std::vector<Source> sources;
  std::vector<std::string> notes;
  if (!GatherSources(o.inputs, o.camera_indices, &sources, &error, &notes, &notes))
    return fail(error);
  for (const std::string& note : notes) std::cerr << "calibrate-camera: " << note << "\n";
  const bool live =
      std::any_of(sources.begin(), sources.end(), [](const Source& s) { return s.live(); });

  g_stop = false;
  std::signal(SIGINT, OnInterrupt);
  ViewCollector collector(*detector, *board, selection);
  collector.Read(sources);
  std::signal(SIGINT, SIG_DFL);
  // Ctrl-C ends a live camera's views; files were meant to be read whole.
  if (g_stop && !live)
    return Fail("calibrate-camera", "interrupted; nothing written", kExitFailure);
  cv::Size size;
  const std::vector<CalibrationView> views = collector.Views(&size);
  if (views.empty()) return Fail("calibrate-camera", "no views to calibrate with", kExitFailure);

  std::cerr << "calibrate-camera: fitting the camera to " << views.size() << " view(s)\n";
  const auto calibration = CalibrateCamera(*board, views, size, calibration_options, &error);
  if (!calibration) {
    return Fail("calibrate-camera",
                error + "; give at least 3 views, better 15-30, at varied tilts", kExitFailure);
  }
  PrintResult(*calibration);
  if (!calibration->doubts.empty() && !o.write_uncertain) {
    return Fail("calibrate-camera",
                "nothing written: the views leave the fit in doubt (above); add views as it "
                "says, or give --write-uncertain to write the file anyway",
                kExitFailure);
  }
  const int code = WriteCalibration(o, *calibration, format);
  if (code != kExitOk) return code;
  return collector.failed() ? kExitFailure : kExitOk;
}

}  // namespace

void RegisterCalibrateCamera(CLI::App& app, Action* action) {
  auto o = std::make_shared<CameraCalibOptions>();
  CLI::App* c = app.add_subcommand(
      "calibrate-camera",
      "Camera intrinsics from images, videos or a live camera of a ChromaTag board "
      "(docs/camera-calibration.md)");
  c->add_option("--board", o->board_file,
                "The board: a sheet from generate --board or calib-sheet (or its sidecar .json), "
                "or a bundle YAML (FILE[#NAME]); planar")
      ->required();
  c->add_option("-o,--output", o->output, "Camera file to write (.yaml)")->required();
  c->add_option("--format", o->format,
                "opencv (cv::FileStorage), ros (camera_info) or kalibr (camchain); detect "
                "--camera reads all three")
      ->capture_default_str()
      ->check(CLI::IsMember({"opencv", "ros", "kalibr"}));
  c->add_option("--model", o->model,
                "pinhole (k1, k2, p1, p2[, k3]) or fisheye (cv::fisheye's equidistant k1-k4)")
      ->capture_default_str()
      ->check(CLI::IsMember({"pinhole", "fisheye"}));
  c->add_flag("--k3", o->k3, "Pinhole: fit k3 as well (wide lenses)");
  c->add_flag("--write-uncertain,--force", o->write_uncertain,
              "Write the camera file even when the fit is in doubt: fewer than 2 views tilted 20 "
              "degrees or more, a standard deviation over 0.5 % of fx or fy or over 1 % of the "
              "image for cx or cy, every view at one distance, fewer than 6 views, or a "
              "projection uncertainty or cross-validation over 0.3 px in the central 80 % of "
              "the image (docs/camera-calibration.md)");
  c->add_option("--distance", o->distance,
                "Where the projection uncertainty and cross-validation are judged: a distance "
                "from the camera (50cm, 2m, ...); default the median distance of the views' "
                "boards");
  c->add_option("--max-views", o->max_views,
                "Most views kept from videos and cameras, chosen for coverage and pose [3, 1000]")
      ->capture_default_str();
  c->add_option("--report", o->reports,
                "Write the report: coverage, residuals, per-view rms, parameters (.pdf or .png; "
                "repeatable)");
  c->add_option("--config", o->config,
                "Detector config JSON (thresholds from 'chromatag calibrate')");
  c->add_option("--camera-name", o->camera_name,
                "Name in the camera file (ROS camera_name, Kalibr /NAME/image_raw)")
      ->capture_default_str();
  c->add_option("--camera-index", o->camera_indices,
                "Read a camera by its index; views are kept as they come until --max-views or "
                "Ctrl-C");
  c->add_option("INPUT", o->inputs,
                "Images (each used), folders, videos (views chosen), /dev/videoN or stream URLs");
  c->callback([o, action] { *action = [o] { return RunCalibrateCamera(*o); }; });
}

}  // namespace chromatag::cli
