#include "chromatag/bench/pair_timing.h"

#include <algorithm>
#include <chrono>

#include "chromatag/bench/comparison.h"
#include "chromatag/bench/metrics.h"
#include "chromatag/detector/detector.h"

namespace chromatag::bench {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

std::vector<PairedFrame> RunPairedTiming(const Dataset& dataset, const DetectorOptions& a,
                                         const DetectorOptions& b,
                                         const internal::StageSwitches& b_switches,
                                         TagDetector& apriltag, TagDetector& aruco,
                                         int render_threads) {
  const std::unique_ptr<Detector> detectors[2] = {Detector::Create(a),
                                                  internal::CreateDetector(b, b_switches)};
  if (!detectors[0] || !detectors[1]) return {};
  const int total = dataset.options().num_frames;
  constexpr int kChunk = 64;
  std::vector<PairedFrame> out(total);
  DetectionResult result;
  std::vector<FoundTag> found;
  volatile uint64_t touched = 0;  // Keeps Touch from being optimised away.
  for (const auto& detector : detectors)
    detector->Detect(dataset.Render(0).bgr, PixelOrder::kBgr, &result);
  for (int first = 0; first < total; first += kChunk) {
    const int count = std::min(kChunk, total - first);
    const std::vector<Frame> frames = RenderFrames(dataset, first, count, render_threads);
    for (int i = 0; i < count; ++i) {
      PairedFrame& record = out[first + i];
      record.has_tags = frames[i].truth.has_tags;
      record.a_first = (first + i) % 2 == 0;
      for (int turn = 0; turn < 2; ++turn) {
        const int which = record.a_first ? turn : 1 - turn;
        aruco.Detect(frames[i].bgr, &found);
        apriltag.Detect(frames[i].bgr, &found);
        touched = touched + TouchFrame(frames[i].bgr);
        const auto start = Clock::now();
        detectors[which]->Detect(frames[i].bgr, PixelOrder::kBgr, &result);
        const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
        const int n = static_cast<int>(result.detections.size());
        (which == 0 ? record.a_us : record.b_us) = us;
        (which == 0 ? record.a_found : record.b_found) = n;
      }
    }
  }
  return out;
}

TimingSetup MakeTimingSetup(DatasetKind kind, int num_frames, uint64_t seed, std::string* error) {
  DatasetOptions options = DatasetOptions::ForKind(kind);
  options.num_frames = num_frames;
  options.seed = seed;
  TimingSetup setup;
  setup.families = DatasetFamilies(kind);
  setup.dataset = Dataset::Create(options, error);
  if (setup.dataset) setup.apriltag = MakeAprilTagDetector(setup.families, error);
  if (setup.apriltag) setup.aruco = MakeArucoDetector(setup.families, error);
  return setup;
}

PairedMedians SummarisePairs(const std::vector<PairedFrame>& frames, bool with_tags) {
  PairedMedians m;
  std::vector<double> a, b, difference, a_first, b_first;
  for (const PairedFrame& f : frames) {
    if (f.has_tags != with_tags) continue;
    ++m.frames;
    a.push_back(f.a_us);
    b.push_back(f.b_us);
    difference.push_back(f.b_us - f.a_us);
    (f.a_first ? a_first : b_first).push_back(f.b_us - f.a_us);
    m.a_found += f.a_found;
    m.b_found += f.b_found;
  }
  m.a_us = Percentile(a, 50);
  m.b_us = Percentile(b, 50);
  m.b_minus_a_us = Percentile(difference, 50);
  m.b_minus_a_a_first_us = Percentile(a_first, 50);
  m.b_minus_a_b_first_us = Percentile(b_first, 50);
  return m;
}

}  // namespace chromatag::bench
