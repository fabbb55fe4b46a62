// Detections as JSON: the one writer of `chromatag detect --json`'s lines and
// of the Python module's Detection.as_dict (which parses this text), so the
// two cannot drift apart. docs/cli.md and docs/python.md show the format.
#ifndef CHROMATAG_DETECTOR_DETECTION_JSON_H_
#define CHROMATAG_DETECTOR_DETECTION_JSON_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection.h"

namespace chromatag {

// One detection as a JSON object on one line: family, id, hamming, margin
// (the decision margin), corners, green_corners and red_corners (lists of
// [x, y], pixels) and, when it has a pose, pose (rvec, tvec, rms_error_px,
// ambiguity). Keys in alphabetical order; numbers as the shortest text that
// reads back to the same double.
std::string DetectionJson(const Detection& detection);

// What a frame's line holds beside its detections.
struct FrameJsonRecord {
  std::string file;  // The input's name as the user gave it; not UTF-8 is written with U+FFFD.
  int frame = 0;     // The frame's index in its input (0 for an image).
  int width = 0;     // Pixels.
  int height = 0;
  double time_us = 0.0;             // DetectorSummary::total_time_us.
  std::optional<double> timestamp;  // Video and live frames: seconds.
  std::string overlay;              // The overlay written for it; empty: none.
  // A board whose pose is asked for: "board" is its pose (null when
  // board_pose is null: not seen). Detections' and tags' indices in the pose
  // are written as their IDs.
  const Board* board = nullptr;
  const BoardPose* board_pose = nullptr;
  // The rejected candidates, when asked for ("rejected"); null: left out.
  const std::vector<RejectedCandidate>* rejected = nullptr;
};

// A frame's line of `chromatag detect --json`, without the newline: the
// record's fields and "detections" (DetectionJson's objects).
std::string FrameJson(const FrameJsonRecord& frame, const std::vector<Detection>& detections);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_DETECTION_JSON_H_
