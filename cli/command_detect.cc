// `chromatag detect`: the detector over images, folders, videos, cameras and
// streams. Frames are decoded and detected on --jobs threads
// (detect_run.h); the output comes in input order (detect_output.h).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <thread>

#include "chromatag/base/units.h"
#include "chromatag/detector/config.h"
#include "chromatag/families/family.h"
#include "chromatag/rig/board_file.h"
#include "chromatag/rig/camera_file.h"
#include "commands.h"
#include "detect_run.h"
#include "detect_signals.h"
#include "sources.h"

namespace chromatag::cli {
namespace {

// The families, config file, camera and tag size of the command line.
bool ToDetectorOptions(const DetectOptions& options, DetectorOptions* detector_options,
                       CameraFileInfo* camera_info, std::string* error) {
  detector_options->families =
      options.family == "all" ? TagFamily::Names() : std::vector<std::string>{options.family};
  detector_options->report_rejected = options.rejected;
  if (!options.config.empty() && !LoadDetectorConfig(options.config, detector_options, error))
    return false;
  if (!options.camera_file.empty()) {
    CameraIntrinsics camera;
    if (!LoadCameraFile(options.camera_file, &camera, error, camera_info)) return false;
    detector_options->camera = camera;
  }
  if (!options.tag_size.empty()) {
    const auto length = ParseLength(options.tag_size, error);
    if (!length) {
      *error = "--tag-size: " + *error;
      return false;
    }
    detector_options->tag_size = length->mm / 1000.0;
  }
  return true;
}

// The board file of --board, whose families the detector then looks for
// (unless --family says otherwise; a --family that leaves the board's out
// would never see it).
std::optional<Board> ReadBoard(const DetectOptions& options, DetectorOptions* detector_options,
                               std::string* error) {
  auto board = ReadBoardFile(options.board_file, error);
  if (!board) return std::nullopt;
  if (!detector_options->camera) {
    *error = "--board needs --camera FILE (the intrinsics)";
    return std::nullopt;
  }
  std::vector<std::string> families;
  for (const BoardTag& tag : board->tags) {
    if (std::find(families.begin(), families.end(), tag.family) == families.end())
      families.push_back(tag.family);
  }
  if (options.family == "all") {
    detector_options->families = families;
  } else if (std::find(families.begin(), families.end(), options.family) == families.end()) {
    *error = "--family " + options.family + " leaves out every tag of the board (" + families[0] +
             (families.size() > 1 ? " and " + families[1] : "") + ")";
    return std::nullopt;
  }
  return board;
}

// What the run needs besides the options, or a message for Fail.
struct Setup {
  DetectorOptions detector_options;
  CameraFileInfo camera_info;
  std::optional<Board> board;
  std::vector<Source> sources;
  std::vector<std::string> skipped;  // Inputs not read (the run then fails).
};

bool Prepare(const DetectOptions& options, Setup* setup, std::string* error) {
  if (!ToDetectorOptions(options, &setup->detector_options, &setup->camera_info, error))
    return false;
  const DetectorOptions& d = setup->detector_options;
  if (!options.board_file.empty() &&
      !(setup->board = ReadBoard(options, &setup->detector_options, error)))
    return false;
  if (d.tag_size > 0 && !d.camera) {
    *error = "pose needs both --camera FILE and --tag-size LENGTH";
    return false;
  }
  if (d.camera && !(d.tag_size > 0) && !setup->board) {
    *error = "pose needs both --camera FILE and --tag-size LENGTH (or --board FILE)";
    return false;
  }
  if (options.smooth && !(d.camera && (d.tag_size > 0 || setup->board))) {
    *error =
        "--smooth smooths poses: it needs --camera FILE with --tag-size LENGTH or --board FILE";
    return false;
  }
  if (options.show && !std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) {
    *error = "--show needs a display (neither DISPLAY nor WAYLAND_DISPLAY is set)";
    return false;
  }
  std::vector<std::string> notes;
  if (!GatherSources(options.inputs, options.camera_indices, &setup->sources, error, &notes,
                     &setup->skipped))
    return false;
  for (const std::string& note : notes) Fail("detect", note, kExitOk);
  for (const Source& source : setup->sources) {
    if (options.smooth && source.kind == SourceKind::kImage) {
      *error = "--smooth follows a pose over the frames of a video or a camera; '" + source.name +
               "' is an image";
      return false;
    }
  }
  for (const std::string& entry : setup->skipped) Fail("detect", entry, kExitOk);
  if (!options.overlay_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.overlay_dir, ec);
    if (ec) {
      *error = "cannot create overlay folder '" + options.overlay_dir + "': " + ec.message();
      return false;
    }
  }
  return true;
}

int RunDetect(const DetectOptions& options) {
  CatchEndingSignals();
  Setup setup;
  std::string error;
  if (!Prepare(options, &setup, &error)) return Fail("detect", error);
  auto detector = Detector::Create(setup.detector_options, &error);
  if (!detector) return Fail("detect", error);
  const int jobs = options.jobs > 0
                       ? options.jobs
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Run run(options, *detector, setup.board, std::move(setup.sources), jobs,
          setup.camera_info.image_size);
  int code = run.Execute();
  if (!setup.skipped.empty() && code == kExitOk) code = kExitFailure;  // An input was not read.
  if (g_signal) DieBy(g_signal);
  ReleaseEndingSignals();
  return code;
}

// What is detected and what is reported.
void AddDetectionOptions(CLI::App* command, DetectOptions* options) {
  command
      ->add_option("--family", options->family,
                   "Tag family: 16h5, 36h11 or all (both; no measurable cost, docs/live.md)")
      ->capture_default_str()
      ->transform(FamilyPrefix())
      ->check(CLI::IsMember({"16h5", "36h11", "all"}));
  command->add_flag("--json", options->json,
                    "One JSON object per frame per line (video and live frames with a timestamp)");
  command->add_option("--overlay", options->overlay_dir,
                      "Write each frame with the detections drawn into this folder "
                      "(<file>_<ext>[_<frame>].png)");
  command->add_option("--camera", options->camera_file,
                      "Camera intrinsics for pose: OpenCV YAML/JSON/XML (camera_matrix, "
                      "distortion_coefficients), ROS camera_info YAML or Kalibr camchain YAML");
  command->add_option("--tag-size", options->tag_size,
                      "Side of the black square, e.g. 40mm, for pose");
  command->add_option("--board", options->board_file,
                      "Report the pose of this board or bundle per frame (with --camera): a "
                      "sheet (or its sidecar .json) or a bundle YAML (FILE[#NAME]); docs/pose.md");
  command->add_option("--config", options->config,
                      "Detector config JSON (thresholds from 'chromatag calibrate')");
  command->add_flag("--smooth", options->smooth,
                    "Videos and cameras: filter each tag's and the board's pose over frames, "
                    "weighing each frame by its covariance and refusing a lone flip "
                    "(docs/pose.md, Pose over time)");
  command->add_flag("--rejected", options->rejected,
                    "Also report the rejected candidates (JSON: \"rejected\") and draw them on "
                    "the overlays, coloured by the stage that rejected them");
}

// The inputs and how they are read.
void AddInputOptions(CLI::App* command, DetectOptions* options) {
  command->add_option("--camera-index", options->camera_indices,
                      "Read a camera by its index (as /dev/videoN); repeatable");
  command->add_flag("--show", options->show,
                    "Show the frames with the detections in a window (q quits)");
  command
      ->add_option("--open-timeout", options->open_timeout_s,
                   "Seconds a stream's server may take to answer before it is given up")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  command
      ->add_option("--max-frames", options->max_frames,
                   "End after this many frames read (images and video frames over all inputs, "
                   "dropped live frames included)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  command
      ->add_option("--duration", options->duration_s,
                   "End the reading this many seconds after it starts (frames under way are "
                   "finished)")
      ->check(CLI::Range(1e-3, 1e9));
  command->add_flag("--every-frame", options->every_frame,
                    "Cameras and streams: detect in every frame, however late, instead of "
                    "dropping frames a newer one has overtaken");
  command
      ->add_option("-j,--jobs", options->jobs,
                   "Threads that decode and detect (default: one per core)")
      ->check(CLI::Range(1, 256));
  command->add_option(
      "INPUT", options->inputs,
      "Images, folders, videos, /dev/videoN or stream URLs (rtsp://, http://, ...); "
      "Ctrl-C, SIGTERM, SIGHUP or SIGQUIT ends a run with its summary (a second one without "
      "waiting for frames "
      "under way)");
}

}  // namespace

void RegisterDetect(CLI::App& app, Action* action) {
  auto options = std::make_shared<DetectOptions>();
  CLI::App* command = app.add_subcommand(
      "detect", "Detect ChromaTags in images, folders, videos, cameras and streams");
  AddDetectionOptions(command, options.get());
  AddInputOptions(command, options.get());
  command->callback([options, action] { *action = [options] { return RunDetect(*options); }; });
}

}  // namespace chromatag::cli
