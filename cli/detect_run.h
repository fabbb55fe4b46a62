// `chromatag detect`'s frame pipeline: a reader thread decodes the sources'
// frames in order (images are decoded by the workers, as their decoding is
// most of the work), `jobs` workers detect, and the calling thread prints
// the outcomes in input order.
#ifndef CHROMATAG_CLI_DETECT_RUN_H_
#define CHROMATAG_CLI_DETECT_RUN_H_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection_json.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/pose_filter.h"
#include "detect_camera.h"
#include "progress.h"
#include "sources.h"

namespace chromatag::cli {

struct DetectOptions {
  std::string family = "all";
  bool json = false;
  std::string overlay_dir;
  std::string camera_file;
  std::string tag_size;
  std::string config;      // Detector config file, e.g. from chromatag calibrate.
  std::string board_file;  // A board or bundle whose pose to report per frame.
  bool rejected = false;   // Report (JSON) and draw (overlay) rejected candidates.
  std::vector<int> camera_indices;
  bool show = false;
  int jobs = 0;                                 // 0: one per core.
  int64_t max_frames = 0;                       // 0: no limit.
  double duration_s = 0.0;                      // 0: no limit.
  double open_timeout_s = kDefaultOpenTimeout;  // For a stream's server to answer.
  bool every_frame = false;                     // Live sources: never drop a stale frame.
  bool smooth = false;  // Videos and cameras: poses filtered over frames (PoseFilter).
  std::vector<std::string> inputs;
};

// What one frame (or one source that could not be read) gives.
struct Task {
  size_t source = 0;
  int frame_index = 0;
  cv::Mat frame;  // Decoded by the reader (videos, cameras, streams) or empty (images).
  // Live: seconds since the epoch when the frame arrived; a video file: the
  // frame's place in it, seconds.
  double timestamp = 0;
  std::string error;  // A source that could not be read: passed on in order.
};

// With --smooth, a frame's own results, kept for the printer, which filters
// the poses in frame order and then writes the frame.
struct PendingFrame {
  size_t source = 0;
  FrameJsonRecord record;  // Its board, board_pose and rejected set when written.
  std::vector<Detection> detections;
  std::optional<BoardPose> board_pose;
  std::vector<RejectedCandidate> rejected;
};

struct Outcome {
  std::string out;
  std::string err;
  bool failed = false;
  bool frame = false;    // A frame was detected in.
  bool dropped = false;  // A live frame dropped unseen: a newer one came first.
  int tags = 0;
  cv::Mat shown;                        // --show: the frame with the detections drawn.
  std::optional<PendingFrame> pending;  // --smooth: `out` is written by the printer.
};

class Run {
 public:
  // `camera_size`: the camera file's recorded image size, if any.
  Run(const DetectOptions& options, const Detector& detector, const std::optional<Board>& board,
      std::vector<Source> sources, int jobs, cv::Size camera_size)
      : options_(options),
        detectors_(detector, camera_size),
        board_(board),
        sources_(std::move(sources)),
        jobs_(jobs),
        capacity_(static_cast<size_t>(2 * jobs + 2)) {}

  // Returns the exit code; a second signal (or a stream stalled after the
  // first) ends the process from here.
  int Execute();

 private:
  // What the printer counted, for the summary.
  struct Tally {
    size_t frames = 0, with_tags = 0, tags = 0, dropped = 0;
    bool failed = false;
    bool reader_stuck = false;   // The reader did not come back after a stop.
    bool duration_over = false;  // --duration was over when the printer stopped.
  };

  // The printer: outcomes in input order until all are printed or the run
  // is stopped.
  void PrintInOrder(bool live, Progress* progress, Tally* tally);
  // The next outcome, waited for; nullopt when there is none to wait for.
  std::optional<Outcome> Next(size_t next, Tally* tally);
  void PrintOutcome(Outcome& outcome, bool live, Progress* progress, Tally* tally);
  // --smooth: the pending frame's poses through their filters, then its
  // output written into outcome->out.
  void WriteSmoothed(Outcome* outcome);
  // The summary line; returns the exit code.
  int Summary(const Tally& tally, Progress* progress);
  [[noreturn]] void EndWithoutThreads(int code);

  void Queue(Task task);
  // Whether --max-frames or --duration ends the reading now.
  bool LimitReached();
  // Tasks the printer has taken; the others are under way. Under mutex_.
  size_t printed() const { return queued_ - tasks_.size() - done_.size() - working_; }
  void Read();
  void ReadVideo(size_t i);
  void Work();
  Outcome Process(Task& task, DetectionResult* result) const;
  // The frame's JSON record, without its board, board pose and rejected
  // candidates (FrameText sets them).
  FrameJsonRecord RecordOf(const Source& source, const Task& task, const DetectionResult& result,
                           const std::string& overlay) const;
  // What stdout gets for the frame: its table lines, or its JSON line.
  std::string FrameText(FrameJsonRecord record, const std::vector<Detection>& detections,
                        const std::optional<BoardPose>& board_pose,
                        const std::vector<RejectedCandidate>& rejected) const;
  // The board's pose in a frame, if seen; a board tag seen twice fails the
  // frame in *outcome instead.
  std::optional<BoardPose> BoardPoseIn(const Source& source, const Task& task,
                                       const DetectionResult& result,
                                       const DetectorOptions& options, Outcome* outcome) const;
  // Draws the frame for --overlay and --show; returns the overlay written.
  std::string Draw(const Source& source, const Task& task, const DetectionResult& result,
                   const DetectorOptions& options, const std::optional<BoardPose>& board_pose,
                   Outcome* outcome) const;

  const DetectOptions& options_;
  const FrameSizeDetectors detectors_;
  const std::optional<Board>& board_;
  const std::vector<Source> sources_;
  const int jobs_;
  const size_t capacity_;
  std::atomic<size_t> total_{0};
  std::chrono::steady_clock::time_point start_;  // When Execute starts.
  // The reader's: frames read so far, and whether a limit ended the reading.
  std::chrono::steady_clock::time_point started_;  // When reading starts.
  int64_t frames_read_ = 0;
  std::atomic<bool> limit_reached_{false};
  std::string limit_;  // Written by the reader before it sets read_all_.
  // When the printer first saw the run stopped with nothing more read.
  std::chrono::steady_clock::time_point stop_seen_;

  std::mutex mutex_;
  std::condition_variable work_ready_, done_changed_, space_;
  std::deque<std::pair<size_t, Task>> tasks_;  // (sequence number, task), in order.
  std::map<size_t, Outcome> done_;             // Finished, waiting to be printed in order.
  size_t queued_ = 0;
  size_t dropped_pending_ = 0;  // Dropped frames in done_, not yet passed by the printer.
  size_t working_ = 0;
  bool read_all_ = false;
  bool closed_ = false;
  bool abandoned_ = false;               // The printer stopped waiting for a stuck reader.
  mutable std::atomic<int> writing_{0};  // Workers inside an overlay's write.
  std::atomic<bool> dying_{false};       // The process ends without the workers.
  // --smooth, the printer's: a filter per source and tag (family, ID), and
  // per source for the board.
  std::map<std::tuple<size_t, std::string, int>, PoseFilter> tag_filters_;
  std::map<size_t, PoseFilter> board_filters_;
};

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_DETECT_RUN_H_
