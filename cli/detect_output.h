// What `chromatag detect` prints and draws for a frame: the table's lines
// (the JSON lines are the detector's FrameJson), and the overlay.
#ifndef CHROMATAG_CLI_DETECT_OUTPUT_H_
#define CHROMATAG_CLI_DETECT_OUTPUT_H_

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "sources.h"

namespace chromatag::cli {

// The table's heading, printed once before the first frame's lines.
inline constexpr char kTableHeading[] =
    "file                            frame  family   id  h  margin  corner 0\n";

// A frame's lines of the table: one per detection (with its pose), "no
// tags" when there is none, and with a board its pose or "not seen".
std::string TableLines(const std::string& name, int frame, const std::vector<Detection>& detections,
                       const Board* board, const std::optional<BoardPose>& board_pose);

// The frame with its detections (outlines, IDs, pose axes), with
// `draw_rejected` the rejected candidates, and the board's axes.
cv::Mat DrawFrame(const cv::Mat& frame, const DetectionResult& result,
                  const DetectorOptions& options, bool draw_rejected, const Board* board,
                  const std::optional<BoardPose>& board_pose);

// Where a frame's overlay goes: <dir>/<stem>.png for an image,
// <dir>/<stem>_<frame>.png for a video's or a live source's frame.
std::string OverlayPath(const std::string& dir, const Source& source, int frame_index);

// Writes `canvas` as a PNG through the all-or-nothing writer. `dying`: the
// run ends without the workers, and no write starts. *writing counts the
// writes under way (with g_writing), for a second signal to wait for.
// False with *error (the reason, without the path) when it is not written.
bool WriteOverlay(const cv::Mat& canvas, const std::string& path, const std::atomic<bool>& dying,
                  std::atomic<int>* writing, std::string* error);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_DETECT_OUTPUT_H_
