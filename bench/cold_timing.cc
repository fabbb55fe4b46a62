// ChromaTag's time on the same frames in four states of the machine's caches
// and branch predictors, to tell how much of tag_comparison's "taking turns"
// median is the detector's own work and how much is coming back to it after
// AprilTag 3 and ArUco have run. Frames are rendered 64 at a time; on each
// chunk, one pass per state, in this order:
//
//   after ArUco and AprilTag 3: then ChromaTag (as pair_timing, and as the
//     worst of tag_comparison's turns).
//   the same, then ChromaTag on two small tag crops: crops around a tag of
//     each family, before the frame: its code and data are back, the
//     frame's content is new to it.
//   frame after frame: as tag_comparison's "ChromaTag alone".
//   the same frame again: ChromaTag on the frame twice in a row; the second.
//
// The frame is read once just before each timed call, as in tag_comparison.
// Run by hand, not by scripts/bench.sh:
//
//   cold_timing [--set camera|classic] [--frames N] [--seed S]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <iostream>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <thread>
#include <vector>

#include "chromatag/bench/comparison.h"
#include "chromatag/bench/competitors.h"
#include "chromatag/bench/dataset.h"
#include "chromatag/bench/pair_timing.h"
#include "chromatag/detector/detector.h"
#include "chromatag/families/family.h"

using namespace chromatag;
using namespace chromatag::bench;

namespace {

constexpr int kStates = 4;
const char* const kStateNames[kStates] = {"after ArUco and AprilTag 3",
                                          "the same, then ChromaTag on two small tag crops",
                                          "frame after frame", "the same frame again"};
// Per state and frame kind (tag-free, with tags): each stage's time, then
// the total, per frame.
using Times = std::array<std::array<std::array<std::vector<double>, kNumStages + 1>, 2>, kStates>;

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// A crop twice the size of a found tag's bounding box, for each family
// looked for: the first tag of at least 60 px that the crop alone still
// yields. Families without one are left out.
std::vector<cv::Mat> TagCrops(const Detector& detector, const std::vector<Frame>& frames,
                              const std::vector<std::string>& families) {
  std::vector<cv::Mat> crops;
  DetectionResult result;
  for (const std::string& family : families) {
    for (const Frame& frame : frames) {
      if (!frame.truth.has_tags) continue;
      detector.Detect(frame.bgr, PixelOrder::kBgr, &result);
      if (result.detections.size() != 1 || result.detections[0].family->name() != family) continue;
      const auto& corners = result.detections[0].corners;
      cv::Rect box = cv::boundingRect(std::vector<cv::Point2f>(corners.begin(), corners.end()));
      if (box.width < 60) continue;
      box = cv::Rect(box.x - box.width / 2, box.y - box.height / 2, 2 * box.width, 2 * box.height) &
            cv::Rect(0, 0, frame.bgr.cols, frame.bgr.rows);
      cv::Mat crop = frame.bgr(box).clone();
      detector.Detect(crop, PixelOrder::kBgr, &result);
      if (result.detections.size() != 1) continue;
      crops.push_back(crop);
      break;
    }
  }
  return crops;
}

// ChromaTag on each frame of a chunk in each of the four states, its times
// added to *times; `found` and `result` are the detectors' buffers, kept
// from chunk to chunk. Returns the frames' touch sum.
uint64_t TimeChunk(const std::vector<Frame>& chunk, const std::vector<cv::Mat>& crops,
                   const Detector& detector, TagDetector& apriltag, TagDetector& aruco,
                   std::vector<FoundTag>* found_buffer, DetectionResult* result_buffer,
                   Times* times) {
  std::vector<FoundTag>& found = *found_buffer;
  DetectionResult& result = *result_buffer;
  uint64_t touched = 0;
  for (int state = 0; state < kStates; ++state) {
    for (const Frame& rendered : chunk) {
      const cv::Mat& frame = rendered.bgr;
      if (state <= 1) {
        aruco.Detect(frame, &found);
        apriltag.Detect(frame, &found);
      }
      if (state == 1) {
        for (const cv::Mat& crop : crops) detector.Detect(crop, PixelOrder::kBgr, &result);
      }
      if (state == 3) detector.Detect(frame, PixelOrder::kBgr, &result);
      touched = touched + TouchFrame(frame);
      detector.Detect(frame, PixelOrder::kBgr, &result);
      auto& out = (*times)[state][rendered.truth.has_tags ? 1 : 0];
      for (int s = 0; s < kNumStages; ++s) out[s].push_back(result.summary.stage_time_us[s]);
      out[kNumStages].push_back(result.summary.total_time_us);
    }
  }
  return touched;
}

// The medians, per kind of frame and state, as a Markdown table.
void PrintTable(const std::string& set, int frames, uint64_t seed, size_t crops,
                const Times& times) {
  std::printf("cold_timing --set %s --frames %d --seed %llu: medians in us, %zu crops\n\n",
              set.c_str(), frames, static_cast<unsigned long long>(seed), crops);
  std::printf("| frames | state | n | total |");
  for (int s = 0; s < kNumStages; ++s) std::printf(" %s |", StageName(static_cast<Stage>(s)));
  std::printf("\n|---|---|---:|---:|");
  for (int s = 0; s < kNumStages; ++s) std::printf("---:|");
  std::printf("\n");
  for (int kind_index : {1, 0}) {
    for (int state = 0; state < kStates; ++state) {
      const auto& out = times[state][kind_index];
      std::printf("| %s | %s | %zu | %.1f |", kind_index ? "with tags" : "tag-free",
                  kStateNames[state], out[kNumStages].size(), Median(out[kNumStages]));
      for (int s = 0; s < kNumStages; ++s) std::printf(" %.1f |", Median(out[s]));
      std::printf("\n");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ChromaTag's time per frame in four states of the caches (see the source)"};
  std::string set = "camera";
  int frames = 2000;
  uint64_t seed = 1;
  app.add_option("--set", set, "data set (as tag_comparison)")
      ->check(CLI::IsMember({"classic", "camera"}))
      ->capture_default_str();
  app.add_option("--frames", frames, "frames to render and time")
      ->check(CLI::Range(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--seed", seed, "data set seed")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help.
    std::cerr << "cold_timing: error: " << e.what() << " (see cold_timing --help)\n";
    return 2;
  }
  cv::setNumThreads(1);  // Every detector on this thread, as in tag_comparison.
  std::string error;
  const TimingSetup setup = MakeTimingSetup(*ParseDatasetKind(set), frames, seed, &error);
  DetectorOptions options;
  options.families = setup.families;
  options.time_stages = true;  // Each stage's median; the clock's cost is in every state.
  const auto detector = setup.aruco ? Detector::Create(options, &error) : nullptr;
  if (!detector) {
    std::cerr << "cold_timing: " << error << "\n";
    return 1;
  }
  TagDetector& apriltag = *setup.apriltag;
  TagDetector& aruco = *setup.aruco;
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  constexpr int kChunk = 64;
  Times times;
  std::vector<cv::Mat> crops;
  std::vector<FoundTag> found;
  DetectionResult result;
  volatile uint64_t touched = 0;  // Keeps TouchFrame from being optimised away.
  for (int first = 0; first < frames; first += kChunk) {
    const std::vector<Frame> chunk =
        RenderFrames(*setup.dataset, first, std::min(kChunk, frames - first), threads);
    if (crops.empty()) crops = TagCrops(*detector, chunk, setup.families);
    touched =
        touched + TimeChunk(chunk, crops, *detector, apriltag, aruco, &found, &result, &times);
  }
  PrintTable(set, frames, seed, crops.size(), times);
  return 0;
}
