#include "chromatag/bench/comparison.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

namespace chromatag::bench {
namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

std::vector<Frame> RenderFrames(const Dataset& dataset, int first, int count, int threads) {
  std::vector<Frame> frames(count);
  std::atomic<int> next{0};
  auto work = [&] {
    for (int i = next++; i < count; i = next++) frames[i] = dataset.Render(first + i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& thread : pool) thread.join();
  return frames;
}

uint64_t TouchFrame(const cv::Mat& image) {
  uint64_t sum = 0;
  for (int y = 0; y < image.rows; ++y) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    for (size_t x = 0; x < image.cols * image.elemSize(); x += 8) sum += row[x];
  }
  return sum;
}

namespace {

// One detector on one frame, timed, scored against the truth, and its pose
// measured when it found the tag. Returns the frame's touch sum.
uint64_t DetectAndScore(const Frame& frame, int d, TagDetector* detector, FrameRecord* record,
                        std::vector<FoundTag>* found) {
  const uint64_t touched = TouchFrame(frame.bgr);
  const auto start = Clock::now();
  detector->Detect(frame.bgr, found);
  const auto end = Clock::now();
  DetectorRecord& out = record->detectors[d];
  out.ran = true;
  out.time_us = std::chrono::duration<double, std::micro>(end - start).count();
  out.num_found = static_cast<int>(found->size());
  const TagTruth* own = nullptr;
  const TagTruth* other = nullptr;
  if (frame.truth.has_tags) {
    own = d == kChromaTag ? &frame.truth.chromatag : &frame.truth.apriltag;
    other = d == kChromaTag ? &frame.truth.apriltag : &frame.truth.chromatag;
  }
  out.score = ScoreFrame(*found, own, other);
  if (out.score.found) {
    const FoundTag& tag = (*found)[out.score.found_index];
    const cv::Matx33d k(own->fx, 0, own->cx, 0, own->fx, own->cy, 0, 0, 1);
    PoseEstimate pose;
    if (detector->Pose(tag, k, 1.0, &pose)) {
      PoseError(pose, *own, &out.rotation_error_deg, &out.translation_error_pct);
      if (d == kAprilTag)
        pose.has_covariance =
            AssumedPoseCovariance(tag, k, 1.0, kAssumedCornerSigmaPx, &pose.covariance);
      PoseNormalisedError(pose, *own, &out.pose_z, &out.pose_nees);
    }
    if (d == kChromaTag && detector->TagDetector::Pose(tag, k, 1.0, &pose)) {
      PoseError(pose, *own, &record->chromatag_four_corner_rotation_error_deg,
                &record->chromatag_four_corner_translation_error_pct);
    }
  }
  return touched;
}

// ChromaTag alone on each frame of a chunk, timed into its record.
// Returns the frames' touch sum.
uint64_t TimeChromaTagAlone(const std::vector<Frame>& frames, ChromaTagDetector& chromatag,
                            FrameRecord* records, std::vector<FoundTag>* found) {
  uint64_t touched = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    touched += TouchFrame(frames[i].bgr);
    const auto start = Clock::now();
    chromatag.Detect(frames[i].bgr, found);
    records[i].chromatag_alone_us =
        std::chrono::duration<double, std::micro>(Clock::now() - start).count();
  }
  return touched;
}

// ChromaTag with the config calibrated for the frame's print; on a tag-free
// frame (no print) every calibrated config, each of which must find nothing.
void RunCalibrated(const Frame& frame, const CalibratedDetectors& calibrated, FrameRecord* record,
                   std::vector<FoundTag>* found) {
  const FrameTruth& truth = record->truth;
  if (truth.has_tags) {
    ChromaTagDetector* detector = calibrated[static_cast<int>(truth.print)];
    if (!detector) return;
    detector->Detect(frame.bgr, found);
    record->calibrated.ran = true;
    record->calibrated.num_found = static_cast<int>(found->size());
    record->calibrated.score = ScoreFrame(*found, &truth.chromatag, &truth.apriltag);
    return;
  }
  for (ChromaTagDetector* detector : calibrated) {
    if (!detector) continue;
    detector->Detect(frame.bgr, found);
    record->calibrated.ran = true;
    record->calibrated.num_found += static_cast<int>(found->size());
    record->calibrated.score.false_positives +=
        ScoreFrame(*found, nullptr, nullptr).false_positives;
  }
}

}  // namespace

std::vector<FrameRecord> RunComparison(const Dataset& dataset, ChromaTagDetector& chromatag,
                                       TagDetector* apriltag, TagDetector* aruco,
                                       const RunOptions& options, RunTimes* times,
                                       const std::function<void(int, int)>& progress,
                                       const CalibratedDetectors& calibrated) {
  const int total = dataset.options().num_frames;
  std::array<TagDetector*, kNumDetectors> detectors = {&chromatag, apriltag, aruco};
  std::vector<FrameRecord> records(total);
  std::vector<FoundTag> found;
  RunTimes local;
  bool warmed_up = false;
  volatile uint64_t touched = 0;  // Keeps Touch from being optimised away.
  for (int first = 0; first < total; first += options.chunk_frames) {
    const int count = std::min(options.chunk_frames, total - first);
    const auto render_start = Clock::now();
    const std::vector<Frame> frames =
        RenderFrames(dataset, first, count, std::max(1, options.render_threads));
    const auto detect_start = Clock::now();
    local.render_s += Seconds(render_start, detect_start);
    if (!warmed_up) {  // First calls allocate; keep them out of the timings.
      for (TagDetector* detector : detectors) {
        for (int i = 0; i < 3 && detector; ++i) detector->Detect(frames[0].bgr, &found);
      }
      for (int i = 0; i < 3; ++i) chromatag.TimeStages(frames[0].bgr);
      warmed_up = true;
    }
    for (int i = 0; i < count; ++i) {
      FrameRecord& record = records[first + i];
      record.truth = frames[i].truth;
      // The detectors take turns at going first.
      for (int turn = 0; turn < kNumDetectors; ++turn) {
        const int d = (first + i + turn) % kNumDetectors;
        if (!detectors[d]) continue;
        touched += DetectAndScore(frames[i], d, detectors[d], &record, &found);
      }
    }
    // ChromaTag again on the chunk, with nothing else in between.
    if (apriltag || aruco)
      touched += TimeChromaTagAlone(frames, chromatag, &records[first], &found);
    local.detect_s += Seconds(detect_start, Clock::now());
    const auto analysis_start = Clock::now();
    for (int i = 0; i < count; ++i)
      records[first + i].chromatag_summary = chromatag.TimeStages(frames[i].bgr);
    for (int i = 0; i < count; ++i)
      RunCalibrated(frames[i], calibrated, &records[first + i], &found);
    for (int i = 0; i < count; ++i) {
      FrameRecord& record = records[first + i];
      if (record.truth.has_tags && !record.detectors[kChromaTag].score.found) {
        record.chromatag_miss = chromatag.ExplainMiss(frames[i].bgr, record.truth);
      }
    }
    local.analysis_s += Seconds(analysis_start, Clock::now());
    if (progress) progress(first + count, total);
  }
  if (times) *times = local;
  return records;
}

}  // namespace chromatag::bench
