#include "detect_output.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "chromatag/base/output_files.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/pose.h"
#include "detect_signals.h"

namespace chromatag::cli {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A table line (names may be long: built as a string, not in a buffer).
std::string BoardLine(const std::string& name, int frame, const Board& board,
                      const std::optional<BoardPose>& pose,
                      const std::vector<Detection>& detections) {
  char head[64];
  std::snprintf(head, sizeof head, " %6d  board ", frame);
  std::string line =
      name + std::string(name.size() < 30 ? 30 - name.size() : 0, ' ') + head + board.name + ": ";
  if (!pose) return line + "not seen\n";
  char body[256];
  const PoseSigma sigma = SigmaOf(pose->covariance);
  std::snprintf(
      body, sizeof body,
      "t = (%g, %g, %g) m  ± %.2g mm, %.2g°  %zu of %zu tags  rms %.2f px  ambiguity %.2f",
      pose->tvec[0], pose->tvec[1], pose->tvec[2], 1000 * sigma.translation,
      sigma.rotation * 180 / kPi, pose->tags_used.size(), board.tags.size(), pose->rms_error_px,
      pose->ambiguity);
  line += body;
  if (!pose->detections_rejected.empty()) {
    line += "  left out: ID";
    for (int i : pose->detections_rejected) line += " " + std::to_string(detections[i].id);
  }
  return line + "\n";
}

// The drawn axes: twice the board's largest tag.
double BoardAxis(const Board& board) {
  double size = 0;
  for (const BoardTag& tag : board.tags) size = std::max(size, tag.size);
  return 2.0 * size;
}

}  // namespace

std::string TableLines(const std::string& name, int frame, const std::vector<Detection>& detections,
                       const Board* board, const std::optional<BoardPose>& board_pose) {
  std::string out;
  for (const Detection& d : detections) {
    char line[512];
    std::snprintf(line, sizeof line, "%-30s %6d  %-6s %4d  %d  %6.1f  (%.1f, %.1f)", name.c_str(),
                  frame, d.family->name().c_str(), d.id, d.hamming, d.decision_margin,
                  d.corners[0].x, d.corners[0].y);
    out += line;
    if (d.has_pose) {
      const PoseSigma sigma = SigmaOf(d.pose.covariance);
      std::snprintf(line, sizeof line, "  t = (%g, %g, %g) m  ± %.2g mm, %.2g°  ambiguity %.2f",
                    d.pose.tvec[0], d.pose.tvec[1], d.pose.tvec[2], 1000 * sigma.translation,
                    sigma.rotation * 180 / kPi, d.pose.ambiguity);
      out += line;
    }
    out += "\n";
  }
  if (detections.empty()) out += name + " frame " + std::to_string(frame) + ": no tags\n";
  if (board) out += BoardLine(name, frame, *board, board_pose, detections);
  return out;
}

cv::Mat DrawFrame(const cv::Mat& frame, const DetectionResult& result,
                  const DetectorOptions& options, bool draw_rejected, const Board* board,
                  const std::optional<BoardPose>& board_pose) {
  cv::Mat canvas = frame.clone();
  if (draw_rejected) DrawRejected(result.rejected, &canvas);
  const CameraIntrinsics* camera = options.camera ? &*options.camera : nullptr;
  DrawDetections(result.detections, camera, options.tag_size, &canvas);
  if (board && board_pose)
    DrawBoardPose(*board_pose, board->name, *options.camera, BoardAxis(*board), &canvas);
  return canvas;
}

std::string OverlayPath(const std::string& dir, const Source& source, int frame_index) {
  char suffix[32];
  std::snprintf(suffix, sizeof suffix, "_%06d", frame_index);
  return (std::filesystem::path(dir) /
          (source.overlay_stem + (source.kind == SourceKind::kImage ? "" : suffix) + ".png"))
      .string();
}

bool WriteOverlay(const cv::Mat& canvas, const std::string& path, const std::atomic<bool>& dying,
                  std::atomic<int>* writing, std::string* error) {
  // Through the same all-or-nothing writer as every other output.
  std::vector<uchar> png;
  std::string why;
  const bool encoded = cv::imencode(".png", canvas, png);
  // A second signal waits for a write under way, and none starts after it
  // (Run::Execute): the process never dies around a write.
  ++*writing;
  ++g_writing;
  const bool written = encoded && !dying && !g_end_after_writes &&
                       WriteFilesAtomically({{path, std::string(png.begin(), png.end())}}, &why);
  --*writing;
  if (--g_writing == 0 && g_end_after_writes) EndBy(g_signal);
  if (!written) *error = why.empty() ? "" : why.substr(why.find("': ") + 3);
  return written;
}

}  // namespace chromatag::cli
