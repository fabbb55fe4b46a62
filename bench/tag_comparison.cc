// tag_comparison: ChromaTag against AprilTag 3 and OpenCV ArUco on the same
// rendered frames. `make bench` runs it on both data sets;
// see docs/benchmarks.md.
//
//   tag_comparison [--set classic|camera] [--detectors all|chromatag]
//                  [--frames N | --quick] [--seed S] [--threads T] [--out DIR]
//                  [--dump-misses DIR]
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "chromatag/bench/comparison.h"
#include "chromatag/bench/prints.h"
#include "chromatag/bench/run_info.h"
#include "chromatag/detector/config.h"

namespace {

using namespace chromatag::bench;

void DrawQuad(cv::Mat& image, const Quad& quad, const cv::Scalar& color, int thickness) {
  for (int i = 0; i < 4; ++i) {
    cv::line(image, cv::Point2d(quad[i]) * 16, cv::Point2d(quad[(i + 1) % 4]) * 16, color,
             thickness, cv::LINE_AA, 4);
  }
  cv::circle(image, cv::Point2d(quad[0]) * 16, 3 * 16, color, thickness, cv::LINE_AA, 4);
}

// A 2x2 montage of frames (two WB, two NWB) with the truth in white and each
// detector's detections in its colour, to show what the data set looks like.
bool WriteExamples(const Dataset& dataset, std::array<TagDetector*, kNumDetectors> detectors,
                   const std::string& path) {
  const cv::Scalar colors[kNumDetectors] = {{40, 40, 215}, {180, 120, 30}, {40, 160, 40}};
  std::vector<cv::Mat> tiles;
  for (int condition = 0; condition < kNumConditions; ++condition) {
    int shown = 0;
    for (int i = 0; i < dataset.options().num_frames && shown < 2; ++i) {
      Frame frame = dataset.Render(i);
      if (!frame.truth.has_tags || static_cast<int>(frame.truth.condition) != condition) continue;
      // One near, fairly frontal view, then one far or steep one.
      const TagTruth& t = frame.truth.chromatag;
      const bool easy = t.size_px >= 60 && t.view_angle_deg <= 45;
      if (easy != (shown == 0)) continue;
      cv::Mat tile = frame.bgr.clone();
      for (int d = 0; d < kNumDetectors; ++d) {
        if (!detectors[d]) continue;
        std::vector<FoundTag> found;
        detectors[d]->Detect(frame.bgr, &found);
        for (const FoundTag& tag : found) DrawQuad(tile, tag.corners, colors[d], 2);
      }
      DrawQuad(tile, frame.truth.chromatag.corners, cv::Scalar(255, 255, 255), 1);
      DrawQuad(tile, frame.truth.apriltag.corners, cv::Scalar(255, 255, 255), 1);
      const FrameTruth& truth = frame.truth;
      const bool camera = truth.kind == DatasetKind::kCamera;
      std::ostringstream label, cast;
      label << (camera ? truth.cast : ConditionName(truth.condition)) << "  " << truth.family
            << "  frame " << i << "  ID " << truth.chromatag.id << "  size "
            << static_cast<int>(truth.chromatag.size_px) << " px  angle "
            << static_cast<int>(truth.chromatag.view_angle_deg) << " deg";
      if (camera) {
        cast << std::fixed << std::setprecision(2) << "red gain " << truth.red_gain
             << ", blue gain " << truth.blue_gain << (truth.mixed_light ? ", mixed light" : "");
      }
      int y = 22;
      for (const std::string& text : {label.str(), cast.str()}) {
        cv::putText(tile, text, {8, y}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {0, 0, 0}, 3, cv::LINE_AA);
        cv::putText(tile, text, {8, y}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 1,
                    cv::LINE_AA);
        y += 22;
      }
      tiles.push_back(tile);
      ++shown;
    }
  }
  if (tiles.size() != 4) return false;
  cv::Mat top, bottom, montage;
  cv::hconcat(tiles[0], tiles[1], top);
  cv::hconcat(tiles[2], tiles[3], bottom);
  cv::vconcat(top, bottom, montage);
  return cv::imwrite(path, montage, {cv::IMWRITE_JPEG_QUALITY, 88});
}

nlohmann::json CornersJson(const std::array<cv::Point2d, 4>& corners) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : corners) out.push_back({p.x, p.y});
  return out;
}

nlohmann::json TagJson(const TagTruth& tag) {
  return {{"id", tag.id},
          {"size_px", tag.size_px},
          {"view_angle_deg", tag.view_angle_deg},
          {"corners", CornersJson(tag.corners)}};
}

// The frame's truth, how it was made, and what the detectors did with it.
nlohmann::json MissJson(const FrameRecord& record) {
  const FrameTruth& t = record.truth;
  nlohmann::json detectors = nlohmann::json::object();
  const char* keys[kNumDetectors] = {"chromatag", "apriltag", "aruco"};
  for (int d = 0; d < kNumDetectors; ++d) {
    const DetectorRecord& r = record.detectors[d];
    if (!r.ran) continue;
    detectors[keys[d]] = {{"found", r.score.found},
                          {"detections", r.num_found},
                          {"false_positives", r.score.false_positives},
                          {"wrong_ids", r.score.wrong_ids},
                          {"time_us", r.time_us}};
  }
  return {{"index", t.index},
          {"set", DatasetKindName(t.kind)},
          {"family", t.family},
          {"quiet_zone_cells", t.quiet_zone_cells},
          {"chromatag", TagJson(t.chromatag)},
          {"apriltag", TagJson(t.apriltag)},
          {"photo", t.photo},
          {"conditions",
           {{"print", PrintKindName(t.print)},
            {"cast", t.cast},
            {"red_gain", t.red_gain},
            {"blue_gain", t.blue_gain},
            {"mixed_light", t.mixed_light},
            {"exposure", t.exposure},
            {"gradient", t.gradient},
            {"tone_gamma", t.tone_gamma},
            {"print_chroma", t.print_chroma},
            {"blur_sigma_px", t.blur_sigma_px},
            {"motion_blur_px", t.motion_blur_px},
            {"noise_sigma_8bit", t.noise_sigma},
            {"shot_snr", t.shot_snr},
            {"read_noise", t.read_noise},
            {"bayer", BayerModeName(t.bayer)},
            {"jpeg_quality", t.jpeg_quality}}},
          {"table_4b",
           {{"stage", MissStageName(record.chromatag_miss.stage)},
            {"reason", record.chromatag_miss.reason},
            {"candidates_on_tag", record.chromatag_miss.candidates}}},
          {"detectors", detectors}};
}

// Writes each frame whose tag ChromaTag missed as frame_NNNNNN.png and
// frame_NNNNNN.json (rendered again: frames are a function of the index).
bool DumpMisses(const Dataset& dataset, const std::vector<FrameRecord>& records,
                const std::string& dir, int* written) {
  *written = 0;
  for (const FrameRecord& record : records) {
    if (!record.truth.has_tags || record.detectors[kChromaTag].score.found) continue;
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d", record.truth.index);
    const std::string stem = dir + "/" + name;
    if (!cv::imwrite(stem + ".png", dataset.Render(record.truth.index).bgr)) return false;
    std::ofstream json(stem + ".json");
    json << MissJson(record).dump(2) << "\n";
    if (!json) return false;
    ++*written;
  }
  return true;
}

// What the command line asks for.
struct Args {
  std::string set = "classic", which_detectors = "all";
  DatasetOptions dataset_options;
  RunOptions run_options;
  bool quick = false;
  std::string out_dir = "bench-results";
  std::string label, dump_dir, config;
  bool skip_calibrated = false;
};

// Parses the command line into *args; an exit code when there is nothing
// more to do (--help, or a bad argument).
std::optional<int> ParseArgs(int argc, char** argv, Args* args) {
  CLI::App app{"ChromaTag against AprilTag 3 and OpenCV ArUco on a rendered data set"};
  app.add_option("--set", args->set,
                 "data set: classic (16h5, kind conditions) or camera (16h5 and 36h11, "
                 "as hard as real cameras)")
      ->check(CLI::IsMember({"classic", "camera"}))
      ->capture_default_str();
  app.add_option("--detectors", args->which_detectors,
                 "all three, or chromatag alone (quick detector iteration; targets relative to "
                 "AprilTag then read n/a)")
      ->check(CLI::IsMember({"all", "chromatag"}))
      ->capture_default_str();
  DatasetOptions& dataset_options = args->dataset_options;
  args->run_options.render_threads = std::max(1u, std::thread::hardware_concurrency());
  app.add_option("--frames", dataset_options.num_frames, "frames to render and detect")
      ->check(CLI::Range(1, 10'000'000))
      ->capture_default_str();
  app.add_flag("--quick", args->quick, "a small run (400 frames) to check that everything works");
  app.add_option("--seed", dataset_options.seed, "data set seed")->capture_default_str();
  app.add_option("--threads", args->run_options.render_threads,
                 "threads rendering frames (detectors always run on one)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--photos", dataset_options.photo_dir, "folder of background photographs")
      ->capture_default_str();
  app.add_option("--out", args->out_dir, "folder for report.md, the PNG figures and frames.csv")
      ->capture_default_str();
  app.add_option("--config", args->config,
                 "ChromaTag's options from a detector config JSON (as 'chromatag detect "
                 "--config'); the set's families replace any it names");
  app.add_option("--label", args->label, "what was measured, for the report (e.g. the commit)");
  app.add_flag("--skip-calibrated", args->skip_calibrated,
               "camera set: do not calibrate for each print and run ChromaTag with those configs");
  app.add_option("--dump-misses", args->dump_dir,
                 "also write each frame whose tag ChromaTag missed to this folder, as PNG with a "
                 "JSON of its truth and Table 4(b)'s reason");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help.
    std::cerr << "tag_comparison: error: " << e.what() << " (see tag_comparison --help)\n";
    return 2;
  }
  if (args->quick && app.count("--frames") == 0) dataset_options.num_frames = 400;
  // The set's own defaults, with what was given on the command line.
  const DatasetOptions given = dataset_options;
  dataset_options = DatasetOptions::ForKind(*ParseDatasetKind(args->set));
  dataset_options.num_frames = given.num_frames;
  dataset_options.seed = given.seed;
  dataset_options.photo_dir = given.photo_dir;
  return std::nullopt;
}

// The camera set's prints, each with ChromaTag on the config calibrated for
// it; false (said on stderr) when a calibration fails.
bool CalibrateForEachPrint(const std::vector<std::string>& families,
                           std::vector<std::unique_ptr<ChromaTagDetector>>* owned,
                           CalibratedDetectors* calibrated,
                           std::vector<std::pair<std::string, chromatag::DetectorOptions>>* used) {
  std::cerr << "tag_comparison: calibrating for each print\n";
  std::string error;
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    auto options = CalibratedOptions(print, &error);
    if (!options) {
      std::cerr << "tag_comparison: calibration for " << PrintKindName(print) << ": " << error
                << "\n";
      return false;
    }
    options->families = families;
    owned->push_back(ChromaTagDetector::CreateWithOptions(*options, &error));
    if (!owned->back()) {
      std::cerr << "tag_comparison: " << error << "\n";
      return false;
    }
    (*calibrated)[k] = owned->back().get();
    used->emplace_back(PrintKindName(print), *options);
  }
  return true;
}

// Progress on stderr: one line redrawn on a terminal, else a line every tenth.
std::function<void(int, int)> ProgressPrinter() {
  const bool terminal = isatty(STDERR_FILENO);
  auto reported = std::make_shared<int>(0);
  return [terminal, reported](int done, int total) {
    if (terminal) {
      std::cerr << "\r  " << done << " / " << total << " frames" << std::flush;
    } else if (done * 10 / total > *reported || done == total) {
      *reported = done * 10 / total;
      std::cerr << "  " << done << " / " << total << " frames\n";
    }
  };
}

// The detectors the run compares.
struct Detectors {
  std::unique_ptr<ChromaTagDetector> chromatag;
  std::unique_ptr<TagDetector> apriltag, aruco;
  std::vector<std::unique_ptr<ChromaTagDetector>> calibrated_owned;
  CalibratedDetectors calibrated{};
  std::vector<std::pair<std::string, chromatag::DetectorOptions>> calibrated_options;
};

// Creates the detectors the arguments ask for; an exit code on failure.
std::optional<int> CreateDetectors(const Args& args, DatasetKind kind, Detectors* out) {
  const std::vector<std::string> families = DatasetFamilies(kind);
  std::string error;
  chromatag::DetectorOptions chromatag_options;
  if (!args.config.empty() &&
      !chromatag::LoadDetectorConfig(args.config, &chromatag_options, &error)) {
    std::cerr << "tag_comparison: " << error << "\n";
    return 2;
  }
  chromatag_options.families = families;
  out->chromatag = ChromaTagDetector::CreateWithOptions(chromatag_options, &error);
  if (!out->chromatag) {
    std::cerr << "tag_comparison: " << error << "\n";
    return args.config.empty() ? 1 : 2;
  }
  if (kind == DatasetKind::kCamera && !args.skip_calibrated &&
      !CalibrateForEachPrint(families, &out->calibrated_owned, &out->calibrated,
                             &out->calibrated_options)) {
    return 1;
  }
  if (args.which_detectors == "all") {
    out->apriltag = MakeAprilTagDetector(families, &error);
    out->aruco = MakeArucoDetector(families, &error);
  }
  return std::nullopt;
}

// The report, the example montage and the missed frames; the exit code.
int WriteOutputs(const Dataset& dataset, const Detectors& detectors,
                 const std::vector<FrameRecord>& records, const ReportInfo& info,
                 const Args& args) {
  std::string markdown, error;
  if (!WriteReport(records, info, args.out_dir, &markdown, &error)) {
    std::cerr << "tag_comparison: " << error << "\n";
    return 1;
  }
  if (!WriteExamples(dataset,
                     {detectors.chromatag.get(), detectors.apriltag.get(), detectors.aruco.get()},
                     args.out_dir + "/examples.jpg")) {
    std::cerr << "tag_comparison: could not write " << args.out_dir << "/examples.jpg\n";
  }
  if (!args.dump_dir.empty()) {
    int written = 0;
    if (!DumpMisses(dataset, records, args.dump_dir, &written)) {
      std::cerr << "tag_comparison: could not write the missed frames to " << args.dump_dir << "\n";
      return 1;
    }
    std::cerr << "tag_comparison: " << written << " missed frames written to " << args.dump_dir
              << "\n";
  }
  std::cout << markdown << "\nWritten to " << args.out_dir << "/report.md\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  if (const auto code = ParseArgs(argc, argv, &args)) return *code;
  const DatasetKind kind = *ParseDatasetKind(args.set);
  const DatasetOptions& dataset_options = args.dataset_options;

  // Every detector on one thread, OpenCV's own pool included (ArUco would
  // otherwise spread over the cores); rendering threads are ours.
  cv::setNumThreads(1);

  std::string error;
  const auto dataset = Dataset::Create(dataset_options, &error);
  if (!dataset) {
    std::cerr << "tag_comparison: " << error << "\n";
    return 2;
  }
  Detectors detectors;
  if (const auto code = CreateDetectors(args, kind, &detectors)) return *code;
  for (const std::string& dir : {args.out_dir, args.dump_dir}) {
    std::error_code ec;
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
    if (ec) {
      std::cerr << "tag_comparison: cannot create " << dir << ": " << ec.message() << "\n";
      return 1;
    }
  }

  std::cerr << "tag_comparison: " << args.set << " set, " << dataset_options.num_frames
            << " frames, seed " << dataset_options.seed << ", " << args.run_options.render_threads
            << " rendering threads\n";
  RunTimes times;
  const std::string load_before = LoadAverage();
  const auto records =
      RunComparison(*dataset, *detectors.chromatag, detectors.apriltag.get(), detectors.aruco.get(),
                    args.run_options, &times, ProgressPrinter(), detectors.calibrated);
  if (isatty(STDERR_FILENO)) std::cerr << "\n";

  ReportInfo info;
  info.command = CommandLine(argc, argv);
  info.label = args.label;
  info.cpu = CpuModel();
#ifdef CHROMATAG_BUILD_FLAGS
  info.build = CHROMATAG_BUILD_FLAGS;
#endif
  info.load = "load average " + load_before + " before the run, " + LoadAverage() + " after";
  info.dataset = dataset_options;
  info.photos = dataset->photos();
  info.times = times;
  const bool all_detectors = args.which_detectors == "all";
  info.active = {true, all_detectors, all_detectors};
  info.calibrated = detectors.calibrated_options;
  return WriteOutputs(*dataset, detectors, records, info, args);
}
