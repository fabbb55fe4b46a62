// The side-by-side comparison: render the data set, run every
// detector on every frame, score, and write the report (the paper's Tables
// 1-4 and Figure 9, corner error, false detections on tag-free frames).
#ifndef CHROMATAG_BENCH_COMPARISON_H_
#define CHROMATAG_BENCH_COMPARISON_H_

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "chromatag/bench/competitors.h"
#include "chromatag/bench/dataset.h"
#include "chromatag/bench/metrics.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag::bench {

// Detectors in report order. ChromaTag is scored against the ChromaTag of
// each frame, the other two against the AprilTag.
enum DetectorIndex { kChromaTag = 0, kAprilTag = 1, kAruco = 2 };
inline constexpr int kNumDetectors = 3;

inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// The corner noise a user of AprilTag 3 is taken to assume for its poses'
// covariance, px per coordinate: about its median corner error on the
// camera set (0.76 px), rounded up.
inline constexpr double kAssumedCornerSigmaPx = 1.0;

struct DetectorRecord {
  bool ran = false;      // False for a detector left out of the run.
  double time_us = 0.0;  // Wall time of the Detect call, one thread.
  int num_found = 0;     // Detections reported.
  FrameScore score;
  // When the tag was found: its pose (TagDetector::Pose) against the truth,
  // the rotation's error in degrees and the translation's in % of the
  // distance; NaN otherwise.
  double rotation_error_deg = std::numeric_limits<double>::quiet_NaN();
  double translation_error_pct = std::numeric_limits<double>::quiet_NaN();
  // And its error in the terms of its covariance (PoseNormalisedError):
  // ChromaTag's own; for AprilTag 3, which gives none, the covariance of
  // kAssumedCornerSigmaPx per corner coordinate (AssumedPoseCovariance);
  // NaN otherwise.
  std::array<double, 6> pose_z = {kNoValue, kNoValue, kNoValue, kNoValue, kNoValue, kNoValue};
  double pose_nees = kNoValue;
};

struct FrameRecord {
  FrameTruth truth;
  std::array<DetectorRecord, kNumDetectors> detectors;
  // Per-stage times and rejections, from a separate pass outside Table 1's
  // timing, with the stages timed (ChromaTagDetector::TimeStages): its
  // total_time_us includes the clock's own cost, unlike
  // detectors[kChromaTag].time_us.
  DetectorSummary chromatag_summary;
  // ChromaTag's time on the frame again, in a pass over each chunk with
  // ChromaTag alone (one call after another on successive frames, as on a
  // thread that runs nothing else); NaN in ChromaTag-only runs, where
  // detectors[kChromaTag].time_us already is that.
  double chromatag_alone_us = std::numeric_limits<double>::quiet_NaN();
  MissCause chromatag_miss;  // Why ChromaTag missed its tag, if it did.
  // ChromaTag's pose from its four outer corners alone, as the other
  // detectors' default (TagDetector::Pose: IPPE_SQUARE), against the truth.
  double chromatag_four_corner_rotation_error_deg = std::numeric_limits<double>::quiet_NaN();
  double chromatag_four_corner_translation_error_pct = std::numeric_limits<double>::quiet_NaN();
  // ChromaTag with the config calibrated for the frame's print
  // (CalibratedDetectors), untimed; ran = false when not run.
  DetectorRecord calibrated;
};

// ChromaTag with the detector config `chromatag calibrate` derives for each
// print of the camera set (CalibratedOptions in prints.h), by PrintKind;
// each runs on the frames of its print. Null entries are not run.
using CalibratedDetectors = std::array<ChromaTagDetector*, kNumPrintKinds>;

struct RunOptions {
  int render_threads = 2;  // Frames are rendered in parallel...
  int chunk_frames = 64;   // ...a chunk at a time, then timed on one thread.
};

struct RunTimes {
  double render_s = 0.0;    // Wall time spent rendering.
  double detect_s = 0.0;    // Wall time spent in the timed detection loop.
  double analysis_s = 0.0;  // Wall time spent explaining ChromaTag's misses (untimed).
};

// Runs the detectors on every frame of `dataset`; for each tag ChromaTag
// misses, runs it again untimed to find out why (FrameRecord::chromatag_miss). Detectors take turns
// going first on successive frames so that none is favoured by a warm cache: each finds the caches
// as the other two left them, as in a pipeline that does other work between frames. With the
// other detectors, ChromaTag is also timed on each chunk alone (FrameRecord::chromatag_alone_us).
// `apriltag` and `aruco` may be null (a ChromaTag-only run; their records then say ran = false).
// `progress(done, total)` is called after each chunk (may be empty). The
// `calibrated` detectors run after the timed loop, on the frames with tags
// of their print (FrameRecord::calibrated).
std::vector<FrameRecord> RunComparison(const Dataset& dataset, ChromaTagDetector& chromatag,
                                       TagDetector* apriltag, TagDetector* aruco,
                                       const RunOptions& options, RunTimes* times,
                                       const std::function<void(int, int)>& progress = {},
                                       const CalibratedDetectors& calibrated = {});

// Frames [first, first + count) of `dataset`, rendered on `threads` threads.
std::vector<Frame> RenderFrames(const Dataset& dataset, int first, int count, int threads);

// Reads every byte of the frame, so that it sits in the caches when a timed
// call starts, whichever detector goes first (a chunk of frames is larger
// than the last-level cache): the paper's repeated-frame condition; a frame
// fresh from the camera would add a memory fetch for any detector. Returns
// a sum, for the caller to keep (else the reads may be optimised away).
uint64_t TouchFrame(const cv::Mat& image);

struct ReportInfo {
  std::string command;  // How the run was started.
  std::string label;    // What was measured (e.g. the commit); may be empty.
  std::string cpu;      // Model name.
  std::string build;    // Build type and code generation flags; may be empty.
  std::string load;     // The machine's load around the run.
  DatasetOptions dataset;
  std::vector<std::string> photos;
  RunTimes times;
  std::array<std::string, kNumDetectors> names = {"ChromaTag", "AprilTag 3", "OpenCV ArUco"};
  std::array<bool, kNumDetectors> active = {true, true, true};  // Which ones ran.
  // The configs of CalibratedDetectors, by print name; empty when not run.
  std::vector<std::pair<std::string, DetectorOptions>> calibrated;
};

// Writes report.md, the PNG figures and frames.csv into `out_dir` (which
// must exist) and returns the Markdown in *markdown.
bool WriteReport(const std::vector<FrameRecord>& records, const ReportInfo& info,
                 const std::string& out_dir, std::string* markdown, std::string* error);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_COMPARISON_H_
