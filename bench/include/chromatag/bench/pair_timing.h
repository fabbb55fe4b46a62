// ChromaTag's time with two sets of detector options, paired frame by frame
// under the comparison's conditions (tag_comparison): on each frame, each
// setting is timed once right after AprilTag 3 and ArUco have run on that
// frame, the two settings taking turns at going first. On this project's
// virtual machines one run's median drifts by up to 20 % from another's an
// hour later, more than most changes to the detector move it; paired on the
// same frames a few seconds apart, both settings see the same drift.
#ifndef CHROMATAG_BENCH_PAIR_TIMING_H_
#define CHROMATAG_BENCH_PAIR_TIMING_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "chromatag/bench/competitors.h"
#include "chromatag/bench/dataset.h"
#include "chromatag/detector/options.h"
#include "stage_switches.h"  // The detector's internal header: bench is not installed.

namespace chromatag::bench {

struct PairedFrame {
  bool has_tags = false;
  double a_us = 0.0, b_us = 0.0;  // ChromaTag's time with each setting.
  int a_found = 0, b_found = 0;   // Detections with each setting.
  bool a_first = true;            // Which setting was timed first.
};

// Times `a` and `b` on every frame of `dataset` as above (frames rendered a
// chunk at a time on `render_threads` threads, then timed on this one).
// `b_switches` turns some of the detector's additions off in b.
std::vector<PairedFrame> RunPairedTiming(const Dataset& dataset, const DetectorOptions& a,
                                         const DetectorOptions& b,
                                         const internal::StageSwitches& b_switches,
                                         TagDetector& apriltag, TagDetector& aruco,
                                         int render_threads);

struct PairedMedians {
  int frames = 0;
  double a_us = 0.0, b_us = 0.0;  // Medians of each setting's times.
  double b_minus_a_us = 0.0;      // Median of the per-frame differences.
  // The same, over the frames on which `a` (then `b`) was timed first:
  // whichever goes first gains a little, and the two orders bracket it.
  double b_minus_a_a_first_us = 0.0, b_minus_a_b_first_us = 0.0;
  int a_found = 0, b_found = 0;  // Detections in all.
};

// Over the frames with tags (`with_tags`) or without; NaN medians where
// there are none.
PairedMedians SummarisePairs(const std::vector<PairedFrame>& frames, bool with_tags);

// What the hand-run timing tools (pair_timing, cold_timing) share: a data
// set of `num_frames` frames of `kind`, and AprilTag 3 and ArUco looking for
// its families. Null members and *error set when one cannot be made.
struct TimingSetup {
  std::vector<std::string> families;
  std::unique_ptr<Dataset> dataset;
  std::unique_ptr<TagDetector> apriltag, aruco;
};
TimingSetup MakeTimingSetup(DatasetKind kind, int num_frames, uint64_t seed, std::string* error);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_PAIR_TIMING_H_
