// ChromaTag's time with its default options and with one of them switched
// off, paired frame by frame after AprilTag 3 and ArUco
// (pair_timing.h): how much a part of the detector costs or saves under the
// comparison's conditions, free of the machine's drift between runs.
//
//   pair_timing [--set camera|classic] [--frames N] [--seed S] (--off OPTION | --on OPTION)
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <string>
#include <thread>

#include "chromatag/bench/competitors.h"
#include "chromatag/bench/dataset.h"
#include "chromatag/bench/pair_timing.h"

using namespace chromatag;
using namespace chromatag::bench;

namespace {

// The second setting: `on` switched on, or `off` switched off, in the
// options or in the stages' switches.
void SwitchOption(const std::string& off, const std::string& on, DetectorOptions* b,
                  internal::StageSwitches* b_switches) {
  if (on == "cast_seeds") {
    b->cast_seeds = true;
  } else if (on == "time_stages") {
    b->time_stages = true;
  } else if (off == "two_step_rises") {
    b->two_step_rises = false;
  } else if (off == "colour_split_read") {
    b_switches->colour_split_read = false;
  } else if (off == "misfit_ratio_read") {
    b_switches->misfit_ratio_read = false;
  } else {
    (off == "quads_from_scans" ? b_switches->quads_from_scans
     : off == "grow_regions"   ? b_switches->grow_regions
                               : b_switches->refine_corners) = false;
  }
}

// The paired medians, with tags and tag-free, as a Markdown table.
void PrintTable(const std::string& set, int frames, uint64_t seed, const std::string& off,
                const std::string& on, const std::vector<PairedFrame>& pairs) {
  std::printf(
      "pair_timing --set %s --frames %d --seed %llu: defaults (A) against %s %s (B), "
      "medians in us\n\n",
      set.c_str(), frames, static_cast<unsigned long long>(seed),
      on.empty() ? off.c_str() : on.c_str(), on.empty() ? "off" : "on");
  std::printf(
      "| frames | n | A | B | B - A, paired | B - A, A timed first | B - A, B timed first | "
      "detections A / B |\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
  for (bool with_tags : {true, false}) {
    const PairedMedians m = SummarisePairs(pairs, with_tags);
    std::printf("| %s | %d | %.1f | %.1f | %+.1f | %+.1f | %+.1f | %d / %d |\n",
                with_tags ? "with tags" : "tag-free", m.frames, m.a_us, m.b_us, m.b_minus_a_us,
                m.b_minus_a_a_first_us, m.b_minus_a_b_first_us, m.a_found, m.b_found);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ChromaTag's time with its defaults and with one option switched, paired frame by frame "
      "after AprilTag 3 and ArUco"};
  std::string set = "camera", off, on;
  int frames = 1500;
  uint64_t seed = 1;
  app.add_option("--set", set, "data set (as tag_comparison)")
      ->check(CLI::IsMember({"classic", "camera"}))
      ->capture_default_str();
  app.add_option("--frames", frames, "frames to render and time")
      ->check(CLI::Range(2, 1'000'000))
      ->capture_default_str();
  app.add_option("--seed", seed, "data set seed")->capture_default_str();
  CLI::Option* off_option =
      app.add_option("--off", off,
                     "the detector's addition (or DetectorOptions switch, on by default) that the "
                     "second setting turns off")
          ->check(CLI::IsMember({"quads_from_scans", "grow_regions", "refine_corners",
                                 "two_step_rises", "colour_split_read", "misfit_ratio_read"}));
  CLI::Option* on_option =
      app.add_option("--on", on,
                     "the DetectorOptions switch, off by default, that the second setting turns on")
          ->check(CLI::IsMember({"cast_seeds", "time_stages"}));
  off_option->excludes(on_option);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help.
    std::cerr << "pair_timing: error: " << e.what() << " (see pair_timing --help)\n";
    return 2;
  }
  if (off.empty() && on.empty()) {
    std::cerr << "pair_timing: error: give --off OPTION or --on OPTION (see pair_timing --help)\n";
    return 2;
  }
  cv::setNumThreads(1);  // Every detector on this thread, as in tag_comparison.
  std::string error;
  const TimingSetup setup = MakeTimingSetup(*ParseDatasetKind(set), frames, seed, &error);
  if (!setup.aruco) {
    std::cerr << "pair_timing: " << error << "\n";
    return 1;
  }
  DetectorOptions a;
  a.families = setup.families;
  DetectorOptions b = a;
  internal::StageSwitches b_switches;
  SwitchOption(off, on, &b, &b_switches);
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const auto pairs =
      RunPairedTiming(*setup.dataset, a, b, b_switches, *setup.apriltag, *setup.aruco, threads);
  PrintTable(set, frames, seed, off, on, pairs);
  return 0;
}
