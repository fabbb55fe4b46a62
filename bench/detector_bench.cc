// The detector on the paper's frame size (752x480, section 5.1), one thread:
// a frame with one tag and the same frame without. Per-stage times are
// reported as counters (microseconds per frame), as in the paper's Table 2.
//
//   ninja -C <build> detector_bench && <build>/bench/detector_bench
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/bench/dataset.h"
#include "chromatag/detector/detector.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

// A natural background, so that FindADiff sees realistic colour edges; the
// tag is 16h5 ID 0 with a 110-pixel black square (the paper's tags reach
// about 126 pixels), rotated and tilted a little.
cv::Mat Frame(bool with_tag) {
  testing::SceneOptions options;
  options.width = 752;
  options.height = 480;
  options.background = cv::imread(CHROMATAG_BENCH_BACKGROUND, cv::IMREAD_COLOR);
  std::vector<testing::SceneTag> tags;
  if (with_tag) {
    testing::SceneTag tag;
    tag.black_square_px = 110;
    tag.centre = {400, 250};
    tag.rotation_deg = 20;
    tag.tilt_deg = 30;
    tags.push_back(tag);
  }
  options.noise_sigma = 2;
  return testing::RenderScene(tags, options).bgr;
}

// The detector's own per-stage times and detections, summed over the
// iterations and reported per frame as counters (the paper's Table 2).
struct StageTotals {
  std::array<double, kNumStages> stage_us{};
  size_t detections = 0;

  void Add(const DetectionResult& result) {
    for (int s = 0; s < kNumStages; ++s) stage_us[s] += result.summary.stage_time_us[s];
    detections += result.detections.size();
  }
  void Report(benchmark::State& state) const {
    const double n = static_cast<double>(state.iterations());
    for (int s = 0; s < kNumStages; ++s)
      state.counters[std::string(StageName(static_cast<Stage>(s))) + "_us"] = stage_us[s] / n;
    state.counters["detections"] = static_cast<double>(detections) / n;
  }
};

void BM_Detect(benchmark::State& state, bool with_tag, std::vector<std::string> families) {
  DetectorOptions options;
  options.families = std::move(families);
  auto detector = Detector::Create(options);
  options.time_stages = true;  // StageTotals, from a twin timed apart.
  auto staged = Detector::Create(options);
  const cv::Mat frame = Frame(with_tag);
  DetectionResult result, staged_result;
  StageTotals totals;
  for (auto _ : state) {
    detector->Detect(frame, PixelOrder::kBgr, &result);
    state.PauseTiming();
    staged->Detect(frame, PixelOrder::kBgr, &staged_result);
    totals.Add(staged_result);
    state.ResumeTiming();
  }
  totals.Report(state);
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_Detect, one_tag_16h5, true, {"16h5"})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Detect, no_tag_16h5, false, {"16h5"})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_Detect, one_tag_both_families, true, {"16h5", "36h11"})
    ->Unit(benchmark::kMicrosecond);

// FindADiff's cost per sample on a plain frame (no candidates at all).
void BM_DetectFlatFrame(benchmark::State& state) {
  auto detector = Detector::Create(DetectorOptions{});
  const cv::Mat frame(480, 752, CV_8UC3, cv::Scalar(128, 128, 128));
  DetectionResult result;
  for (auto _ : state) detector->Detect(frame, PixelOrder::kBgr, &result);
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_DetectFlatFrame)->Unit(benchmark::kMicrosecond);

// The first frames of the camera set (bench/include/chromatag/bench/
// dataset.h), both families: noise, casts, blur, demosaicing and JPEG as
// tag_comparison renders them, cycled through so that each iteration is a
// different frame, read once before the timed call so that it sits in the
// caches (as tag_comparison does: 400 frames do not fit). tag_comparison
// reports medians over thousands of such frames; this is the quick loop to
// profile (perf record) and to compare builds.
const std::vector<cv::Mat>& CameraFrames(bool with_tags) {
  static const std::array<std::vector<cv::Mat>, 2> frames = [] {
    constexpr int kFrames = 400;
    bench::DatasetOptions options = bench::DatasetOptions::ForKind(bench::DatasetKind::kCamera);
    options.num_frames = kFrames;
    std::array<std::vector<cv::Mat>, 2> out;
    std::string error;
    auto dataset = bench::Dataset::Create(options, &error);
    if (!dataset) return out;
    for (int i = 0; i < kFrames; ++i) {
      bench::Frame frame = dataset->Render(i);
      out[frame.truth.has_tags ? 1 : 0].push_back(std::move(frame.bgr));
    }
    return out;
  }();
  return frames[with_tags ? 1 : 0];
}

// A buffer larger than the last-level cache, written between frames in the
// cold variants: what another detector, or the rest of a robot's pipeline,
// leaves in the caches when it runs between two frames (tag_comparison's
// all-detector runs take turns in this way). The frame itself is still read
// into the caches before the timed call.
void EvictCaches() {
  static std::vector<uint8_t> buffer(64 << 20);
  static uint8_t value = 0;
  ++value;
  for (size_t i = 0; i < buffer.size(); i += 64) buffer[i] = value;
}

void BM_CameraSet(benchmark::State& state, bool with_tags, bool cold) {
  const std::vector<cv::Mat>& frames = CameraFrames(with_tags);
  if (frames.empty()) {
    state.SkipWithError("the camera set could not be rendered (photographs missing?)");
    return;
  }
  DetectorOptions options;
  options.families = {"16h5", "36h11"};
  auto detector = Detector::Create(options);
  options.time_stages = true;  // StageTotals, from a twin timed apart.
  auto staged = Detector::Create(options);
  DetectionResult result, staged_result;
  StageTotals totals;
  size_t next = 0;
  volatile uint64_t touched = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const cv::Mat& frame = frames[next];
    staged->Detect(frame, PixelOrder::kBgr, &staged_result);
    totals.Add(staged_result);
    if (cold) EvictCaches();
    for (int y = 0; y < frame.rows; ++y) {
      const uint8_t* row = frame.ptr<uint8_t>(y);
      for (int x = 0; x < frame.cols * 3; x += 64) touched += row[x];
    }
    state.ResumeTiming();
    detector->Detect(frame, PixelOrder::kBgr, &result);
    next = (next + 1) % frames.size();
  }
  totals.Report(state);
  state.counters["frames"] = static_cast<double>(frames.size());
}
BENCHMARK_CAPTURE(BM_CameraSet, with_tags, true, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CameraSet, tag_free, false, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CameraSet, with_tags_cold, true, true)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_CameraSet, tag_free_cold, false, true)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace chromatag

BENCHMARK_MAIN();
