// calib_comparison: camera calibration from views of a ChromaTag board
// against OpenCV's ChArUco calibration of a board of the same size, on the
// same simulated camera and the same board poses (src/calib_trial.h).
// scripts/bench.sh runs it; docs/benchmarks/camera-calibration.md is its
// report.
//
//   calib_comparison [--trials N] [--views N] [--seed S] [--threads T]
//                    [--label L] [--out DIR]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "chromatag/bench/run_info.h"
#include "src/calib_report.h"
#include "src/calib_trial.h"

namespace {

// What the command line asks for.
struct Args {
  int trials = 5;
  chromatag::bench::TrialOptions options;
  std::string out_dir = "calib-results", label;
};

// Parses the command line into *args; an exit code when there is nothing
// more to do (--help, or a bad argument).
std::optional<int> ParseArgs(int argc, char** argv, Args* args) {
  CLI::App app{
      "Camera calibration from a ChromaTag board against OpenCV's ChArUco calibration, on the "
      "same simulated camera and board poses"};
  chromatag::bench::TrialOptions& options = args->options;
  options.render_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--trials", args->trials, "trials, each with its own poses and camera effects")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--views", options.views, "board poses per trial (both boards at each)")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  app.add_option("--seed", options.seed, "seed of the poses and camera effects")
      ->capture_default_str();
  app.add_option("--threads", options.render_threads,
                 "threads rendering views (detection and calibration always run on one)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app.add_option("--label", args->label, "what was measured, for the report (e.g. the commit)");
  app.add_option("--out", args->out_dir, "folder for report.md and results.json")
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help.
    std::cerr << "calib_comparison: error: " << e.what() << " (see calib_comparison --help)\n";
    return 2;
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace chromatag::bench;
  Args args;
  if (const auto code = ParseArgs(argc, argv, &args)) return *code;
  const TrialOptions& options = args.options;
  const int trials = args.trials;
  const std::string& out_dir = args.out_dir;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::cerr << "calib_comparison: cannot create " << out_dir << ": " << ec.message() << "\n";
    return 1;
  }
  // Detection and calibration on this thread alone, OpenCV's included, so
  // that their times compare; the rendering threads are ours.
  cv::setNumThreads(1);
  const auto start = std::chrono::steady_clock::now();
  const std::string load_before = LoadAverage();
  std::string error;
  const auto setup = MakeCalibrationSetup(&error);
  if (!setup) {
    std::cerr << "calib_comparison: " << error << "\n";
    return 1;
  }
  CalibrationRunInfo info;
  info.options = options;
  std::vector<TrialResult> results;
  for (int t = 0; t < trials; ++t) {
    results.push_back(RunCalibrationTrial(*setup, options, t));
    info.render_s += results.back().render_s;
    std::cerr << "calib_comparison: trial " << t + 1 << " of " << trials << " done\n";
  }
  info.command = CommandLine(argc, argv);
  info.label = args.label;
  info.cpu = CpuModel();
#ifdef CHROMATAG_BUILD_FLAGS
  info.build = CHROMATAG_BUILD_FLAGS;
#endif
  info.load = "load average " + load_before + " before the run, " + LoadAverage() + " after";
  info.total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  info.chromatag_board = setup->chromatag.description;
  info.charuco_board = setup->charuco.description;
  std::string markdown;
  if (!WriteCalibrationReport(results, info, out_dir, &markdown, &error)) {
    std::cerr << "calib_comparison: " << error << "\n";
    return 1;
  }
  std::cout << markdown << "\nWritten to " << out_dir << "/report.md\n";
  return 0;
}
