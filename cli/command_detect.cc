// `chromatag detect`: the detector over images, folders, videos, cameras and
// streams. Frames are decoded and detected on --jobs threads; the output
// comes in input order.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <condition_variable>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <thread>

#include "chromatag/calib/board_file.h"
#include "chromatag/calib/camera_file.h"
#include "chromatag/detector/board.h"
#include "chromatag/detector/camera.h"
#include "chromatag/detector/config.h"
#include "chromatag/detector/detection_json.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/families/family.h"
#include "chromatag/generator/file_util.h"
#include "chromatag/generator/units.h"
#include "commands.h"
#include "flag_terms.h"
#include "library_output.h"
#include "progress.h"
#include "sources.h"

namespace chromatag::cli {
namespace {

namespace fs = std::filesystem;

// How often waits look at the signal flags.
constexpr std::chrono::milliseconds kPoll(50);
// How long, after Ctrl-C, every frame read so far is printed and the reader
// has still not come back (a stream that stalled in its open or a read),
// before the run ends without it.
constexpr std::chrono::milliseconds kReaderGrace(1000);

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
  std::vector<std::string> inputs;
};

// Ctrl-C (SIGINT), SIGTERM, SIGHUP (the terminal closed) or SIGQUIT
// (Ctrl-backslash): the first ends the reading, the frames under
// way finish and are printed, then the summary; a second one stops waiting
// for them (a stalled stream, a slow frame) and prints the summary at once.
// Either way every printed line is whole, and the exit code is 128 + the
// signal, as a shell expects.
constexpr int kEndingSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
std::atomic<bool> g_stop{false};
std::atomic<bool> g_stop_now{false};
std::atomic<int> g_signal{0};
// Workers inside an overlay's write, and whether the process is to end as
// soon as the last of them is done.
std::atomic<int> g_writing{0};
std::atomic<bool> g_end_after_writes{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "used in a signal handler");

// Ends the process by `signal`, its default action.
void EndBy(int signal) {
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void OnSignal(int signal) {
  g_signal = signal;
  if (!g_stop.exchange(true)) return;
  if (!g_stop_now.exchange(true)) return;
  // A third signal ends the process at once, whatever it is stuck in, but
  // not around an overlay being written (it would leave its temporaries):
  // then the write ends it. A fourth does not wait even for that.
  if (g_writing == 0 || g_end_after_writes.exchange(true)) EndBy(signal);
}

// Ends the process by `signal` itself, its handler reset, after the summary:
// a shell then knows the job was interrupted (a loop over files stops too).
[[noreturn]] void DieBy(int signal) {
  std::fflush(stdout);
  std::fflush(ToolErr());
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);
}

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

struct Outcome {
  std::string out;
  std::string err;
  bool failed = false;
  bool frame = false;    // A frame was detected in.
  bool dropped = false;  // A live frame dropped unseen: a newer one came first.
  int tags = 0;
  cv::Mat shown;  // --show: the frame with the detections drawn.
};

// The run: a reader thread decodes the sources' frames in order (images are
// decoded by the workers, as their decoding is most of the work), `jobs`
// workers detect, and the calling thread prints the outcomes in order.
class Run {
 public:
  Run(const DetectOptions& options, const Detector& detector, const std::optional<Board>& board,
      std::vector<Source> sources, int jobs, cv::Size camera_size)
      : options_(options),
        detector_(detector),
        camera_size_(camera_size),
        board_(board),
        sources_(std::move(sources)),
        jobs_(jobs),
        capacity_(static_cast<size_t>(2 * jobs + 2)) {}

  // Returns the exit code.
  int Execute() {
    bool live = false;
    size_t images = 0;
    for (const Source& s : sources_) {
      live |= s.live();
      images += s.kind == SourceKind::kImage ? 1 : 0;
    }
    total_ = images;
    Progress progress("detect", "frames", live ? 0 : total_.load());
    const auto start = std::chrono::steady_clock::now();
    std::thread reader([this] { Read(); });
    std::vector<std::thread> workers;
    for (int i = 0; i < jobs_; ++i) workers.emplace_back([this] { Work(); });
    if (!options_.json)
      std::cout << "file                            frame  family   id  h  margin  corner 0\n";
    size_t frames = 0, with_tags = 0, tags = 0, dropped = 0;
    bool failed = false;
    bool reader_stuck = false, duration_over = false;
    std::chrono::steady_clock::time_point stop_seen;
    for (size_t next = 0; !g_stop_now; ++next) {
      Outcome outcome;
      {
        // Polled: a signal handler cannot wake a condition variable.
        std::unique_lock<std::mutex> lock(mutex_);
        const auto ready = [&] { return done_.count(next) || (read_all_ && next == queued_); };
        // Stopped (a signal, or --duration over), every frame read printed
        // for kReaderGrace, and the reader still in a read (or an open) that
        // does not return. Nothing is queued after that (abandoned_).
        const auto stuck = [&] {
          const auto now = std::chrono::steady_clock::now();
          duration_over = options_.duration_s > 0 &&
                          std::chrono::duration<double>(now - start).count() >= options_.duration_s;
          if (!(g_stop || duration_over) || next != queued_) {
            stop_seen = std::chrono::steady_clock::time_point();
            return false;
          }
          if (stop_seen == std::chrono::steady_clock::time_point()) stop_seen = now;
          return abandoned_ = now - stop_seen >= kReaderGrace;
        };
        while (!ready() && !g_stop_now && !(reader_stuck = stuck()))
          done_changed_.wait_for(lock, kPoll);
        if (!done_.count(next)) break;
        outcome = std::move(done_[next]);
        done_.erase(next);
        if (outcome.dropped) --dropped_pending_;
      }
      space_.notify_all();
      if (outcome.dropped) {
        ++dropped;
        continue;
      }
      std::cout << outcome.out << std::flush;
      if (!outcome.err.empty()) {
        progress.Finish();  // The message on a line of its own; the bar comes back.
        std::cerr << outcome.err;
      }
      failed |= outcome.failed;
      if (outcome.frame) {
        ++frames;
        with_tags += outcome.tags > 0 ? 1 : 0;
        tags += static_cast<size_t>(outcome.tags);
      }
      if (!live) progress.set_total(total_);
      progress.Update(frames);
      if (options_.show && !outcome.shown.empty()) {
        cv::imshow("chromatag detect", outcome.shown);
        const int key = cv::waitKey(1);
        if (key == 'q' || key == 27) g_stop = true;
      }
    }
    const auto summary = [&] {
      progress.Finish();
      std::cout.flush();
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::string ended = g_signal                        ? " (interrupted)"
                          : limit_reached_                ? " (" + limit_ + ")"
                          : reader_stuck && duration_over ? " (--duration, the stream stalled)"
                                                          : "";
      if (dropped) ended += ", " + std::to_string(dropped) + " stale live frames dropped";
      std::fprintf(ToolErr(),
                   "detect: %zu frame%s, %zu with tags, %zu tag%s in %.2f s: %.1f frames/s on %d "
                   "thread%s%s\n",
                   frames, frames == 1 ? "" : "s", with_tags, tags, tags == 1 ? "" : "s", seconds,
                   seconds > 0 ? static_cast<double>(frames) / seconds : 0.0, jobs_,
                   jobs_ == 1 ? "" : "s", ended.c_str());
      std::fflush(ToolErr());
      return failed ? kExitFailure : kExitOk;
    };
    if (g_stop_now || reader_stuck) {
      // A second signal, or a reader stuck in a stalled stream after the
      // first: the reader (and after a second signal the workers) cannot be
      // waited for. The printed lines are whole, the summary says how many,
      // and the process ends here. Overlays are written through temporary
      // files, so none is left half-written.
      const int code = summary();
      // A worker writing an overlay has signals blocked in its thread, but
      // the process would die around it: let the write end (a PNG takes
      // milliseconds; a stuck disk is not waited for past two seconds).
      dying_ = true;
      for (int i = 0; writing_ > 0 && i < 200; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (g_signal) DieBy(g_signal);
      std::_Exit(code);  // Stopped from the --show window.
    }
    reader.join();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    work_ready_.notify_all();
    for (std::thread& w : workers) w.join();
    return summary();
  }

 private:
  // Queues a task in order, waiting while `capacity_` frames are under way.
  // A live frame instead replaces the frames of its source still waiting for
  // a worker (they are stale now; each is reported as dropped), unless
  // --every-frame.
  void Queue(Task task) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (abandoned_) return;  // The run has ended without the reader.
    if (sources_[task.source].live() && !options_.every_frame) {
      for (auto it = tasks_.begin(); it != tasks_.end();) {
        if (it->second.source != task.source || !it->second.error.empty()) {
          ++it;
          continue;
        }
        Outcome dropped;
        dropped.dropped = true;
        done_[it->first] = std::move(dropped);
        ++dropped_pending_;
        it = tasks_.erase(it);
      }
      done_changed_.notify_all();
    }
    // Dropped frames hold no image: they do not take room.
    while (queued_ - printed() - dropped_pending_ >= capacity_ && !g_stop_now)
      space_.wait_for(lock, kPoll);
    tasks_.push_back({queued_++, std::move(task)});
    lock.unlock();
    work_ready_.notify_one();
  }

  // The detector for frames of `size`: the camera file's intrinsics are for
  // the image size it records. Frames of another size with the same aspect
  // get them scaled; of another shape, the intrinsics as they are, with a
  // warning that their poses are wrong. Either is said once per size, in
  // *note.
  const Detector& DetectorFor(cv::Size size, std::string* note) const {
    const auto& camera = detector_.options().camera;
    if (!camera || camera_size_.empty() || size == camera_size_) return detector_;
    std::lock_guard<std::mutex> lock(scaled_mutex_);
    const auto key = std::make_pair(size.width, size.height);
    auto found = scaled_.find(key);
    if (found != scaled_.end()) return found->second ? *found->second : detector_;
    const auto intrinsics = IntrinsicsForFrame(*camera, camera_size_, size);
    char text[320];
    std::unique_ptr<Detector> scaled;
    if (intrinsics) {
      DetectorOptions options = detector_.options();
      options.camera = *intrinsics;
      scaled = Detector::Create(options);
      std::snprintf(text, sizeof text,
                    "chromatag detect: warning: the camera file is for %d x %d frames; %d x %d "
                    "frames use its intrinsics scaled by %.4g\n",
                    camera_size_.width, camera_size_.height, size.width, size.height,
                    static_cast<double>(size.width) / camera_size_.width);
    } else {
      std::snprintf(text, sizeof text,
                    "chromatag detect: warning: the camera file is for %d x %d frames; %d x %d "
                    "frames have another shape, and their poses are wrong (calibrate the "
                    "camera at this size)\n",
                    camera_size_.width, camera_size_.height, size.width, size.height);
    }
    *note += text;
    auto& entry = scaled_[key];
    entry = std::move(scaled);
    return entry ? *entry : detector_;
  }

  // Whether --max-frames or --duration ends the reading now.
  bool LimitReached() {
    if (options_.max_frames > 0 && frames_read_ >= options_.max_frames) {
      limit_ = "--max-frames " + std::to_string(options_.max_frames);
    } else if (options_.duration_s > 0 &&
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() >=
                   options_.duration_s) {
      char text[48];
      std::snprintf(text, sizeof text, "--duration %g s", options_.duration_s);
      limit_ = text;
    } else {
      return false;
    }
    limit_reached_ = true;
    return true;
  }

  // Tasks the printer has taken; the others are under way. Under mutex_.
  size_t printed() const { return queued_ - tasks_.size() - done_.size() - working_; }

  void Read() {
    started_ = std::chrono::steady_clock::now();
    for (size_t i = 0; i < sources_.size() && !g_stop && !LimitReached(); ++i) {
      const Source& source = sources_[i];
      if (source.kind == SourceKind::kImage) {
        ++frames_read_;
        Queue({i, 0, {}, 0, {}});
        continue;
      }
      cv::VideoCapture capture;
      const auto opening = std::chrono::steady_clock::now();
      if (!OpenSource(source, options_.open_timeout_s, &capture)) {
        const double waited =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - opening).count();
        char timed_out[96] = "";
        if (source.kind == SourceKind::kStream && waited >= 0.9 * options_.open_timeout_s) {
          std::snprintf(timed_out, sizeof timed_out,
                        " (no answer within %g s; --open-timeout sets the wait)",
                        options_.open_timeout_s);
        }
        Queue({i,
               0,
               {},
               0,
               std::string("cannot open ") +
                   (source.kind == SourceKind::kVideo ? "video"
                    : source.live()                   ? "camera or stream"
                                                      : "") +
                   " '" + source.name + "'" + timed_out + ", skipped"});
        continue;
      }
      if (!source.live())
        total_ += static_cast<size_t>(std::max(0.0, capture.get(cv::CAP_PROP_FRAME_COUNT)));
      int index = 0;
      while (!g_stop && !LimitReached()) {
        cv::Mat frame;  // A new buffer each time: the workers keep the last ones.
        if (!capture.read(frame) || frame.empty()) break;
        if (frame.type() != CV_8UC3) {
          Queue({i, index, {}, 0, "'" + source.name + "' gives frames that are not 8-bit colour"});
          break;
        }
        // Live: when the frame arrived (seconds since the epoch); a video
        // file: the frame's place in it (seconds from its start).
        const double timestamp =
            source.live()
                ? std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
                      .count()
                : capture.get(cv::CAP_PROP_POS_MSEC) / 1000.0;
        ++frames_read_;
        Queue({i, index++, std::move(frame), timestamp, {}});
      }
      if (index == 0 && !g_stop && !limit_reached_)
        Queue({i, 0, {}, 0, "no frames in '" + source.name + "', skipped"});
    }
    std::lock_guard<std::mutex> lock(mutex_);
    read_all_ = true;
    done_changed_.notify_all();
  }

  void Work() {
    DetectionResult result;
    for (;;) {
      std::pair<size_t, Task> item;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        work_ready_.wait(lock, [&] { return !tasks_.empty() || closed_; });
        if (tasks_.empty()) return;
        item = std::move(tasks_.front());
        tasks_.pop_front();
        ++working_;
      }
      Outcome outcome;
      try {
        outcome = Process(item.second, &result);
      } catch (const std::exception& e) {
        // OpenCV throws on images it cannot hold (a 40000 x 40000 PNG): one
        // line for that input, and the run goes on.
        outcome = Outcome();
        outcome.err = "chromatag detect: cannot process '" + sources_[item.second.source].name +
                      "': " + e.what() + ", skipped\n";
        outcome.failed = true;
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        --working_;
        done_[item.first] = std::move(outcome);
      }
      done_changed_.notify_all();
    }
  }

  Outcome Process(Task& task, DetectionResult* result) const {
    Outcome outcome;
    const Source& source = sources_[task.source];
    if (!task.error.empty()) {
      outcome.err = "chromatag detect: " + task.error + "\n";
      outcome.failed = true;
      return outcome;
    }
    if (source.kind == SourceKind::kImage) {
      std::string error;
      task.frame = ReadImage(source.name, &error);
      if (task.frame.empty()) {
        outcome.err = "chromatag detect: " + InFlagTerms(error) + ", skipped\n";
        outcome.failed = true;
        return outcome;
      }
    }
    const cv::Mat& frame = task.frame;
    const Detector& detector = DetectorFor(frame.size(), &outcome.err);
    detector.Detect(frame, PixelOrder::kBgr, result);
    outcome.frame = true;
    outcome.tags = static_cast<int>(result->detections.size());
    const DetectorOptions& d = detector.options();
    std::optional<BoardPose> board_pose;
    if (board_) {
      // A board tag seen twice in one frame: a frame spliced from two (a
      // video cut mid-frame) or two boards in view. Its pose is not
      // reported, and the frame is named.
      std::map<std::pair<std::string, int>, int> seen;
      std::string twice;
      for (const Detection& det : result->detections) {
        if (board_->Find(det.family->name(), det.id) >= 0 &&
            ++seen[{det.family->name(), det.id}] == 2)
          twice += (twice.empty() ? "" : ", ") + std::to_string(det.id);
      }
      BoardPose pose;
      if (!twice.empty()) {
        outcome.err += "chromatag detect: '" + source.name + "' frame " +
                       std::to_string(task.frame_index) + ": board tag(s) " + twice +
                       " seen twice (a damaged or spliced frame, or two boards in view): no board "
                       "pose, skipped\n";
        outcome.failed = true;
      } else if (EstimateBoardPose(result->detections, *board_, *d.camera, &pose)) {
        board_pose = pose;
      }
    }
    std::string overlay;
    if (!options_.overlay_dir.empty() || options_.show) {
      cv::Mat canvas = frame.clone();
      if (options_.rejected) DrawRejected(result->rejected, &canvas);
      DrawDetections(result->detections, d.camera ? &*d.camera : nullptr, d.tag_size, &canvas);
      if (board_pose) DrawBoardPose(*board_pose, board_->name, *d.camera, BoardAxis(), &canvas);
      if (!options_.overlay_dir.empty()) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, "_%06d", task.frame_index);
        overlay =
            (fs::path(options_.overlay_dir) /
             (source.overlay_stem + (source.kind == SourceKind::kImage ? "" : suffix) + ".png"))
                .string();
        // Through the same all-or-nothing writer as every other output.
        std::vector<uchar> png;
        std::string why;
        const bool encoded = cv::imencode(".png", canvas, png);
        // A second signal waits for a write under way, and none starts after
        // it (Execute): the process never dies around a write.
        ++writing_;
        ++g_writing;
        const bool written =
            encoded && !dying_ && !g_end_after_writes &&
            WriteFilesAtomically({{overlay, std::string(png.begin(), png.end())}}, &why);
        --writing_;
        if (--g_writing == 0 && g_end_after_writes) EndBy(g_signal);
        if (!written) {
          outcome.err = "chromatag detect: cannot write overlay '" + overlay + "'" +
                        (why.empty() ? "" : ": " + why.substr(why.find("': ") + 3)) + "\n";
          outcome.failed = true;
          overlay.clear();
        }
      }
      if (options_.show) outcome.shown = canvas;
    }
    if (options_.json) {
      FrameRecord record;
      record.file = source.name;
      record.frame = task.frame_index;
      record.width = frame.cols;
      record.height = frame.rows;
      record.time_us = result->summary.total_time_us;
      if (source.kind != SourceKind::kImage) record.timestamp = task.timestamp;
      record.overlay = overlay;
      record.board = board_ ? &*board_ : nullptr;
      record.board_pose = board_pose ? &*board_pose : nullptr;
      record.rejected = options_.rejected ? &result->rejected : nullptr;
      outcome.out = FrameJson(record, result->detections) + "\n";
    } else {
      for (const Detection& d : result->detections) {
        char line[512];
        std::snprintf(line, sizeof line, "%-30s %6d  %-6s %4d  %d  %6.1f  (%.1f, %.1f)",
                      source.name.c_str(), task.frame_index, d.family->name().c_str(), d.id,
                      d.hamming, d.decision_margin, d.corners[0].x, d.corners[0].y);
        outcome.out += line;
        if (d.has_pose) {
          std::snprintf(line, sizeof line, "  t = (%g, %g, %g) m  ambiguity %.2f", d.pose.tvec[0],
                        d.pose.tvec[1], d.pose.tvec[2], d.pose.ambiguity);
          outcome.out += line;
        }
        outcome.out += "\n";
      }
      if (result->detections.empty())
        outcome.out += source.name + " frame " + std::to_string(task.frame_index) + ": no tags\n";
      if (board_)
        outcome.out += BoardLine(source.name, task.frame_index, board_pose, result->detections);
    }
    return outcome;
  }

  // A table line (names may be long: built as a string, not in a buffer).
  std::string BoardLine(const std::string& name, int frame, const std::optional<BoardPose>& pose,
                        const std::vector<Detection>& detections) const {
    char head[64];
    std::snprintf(head, sizeof head, " %6d  board ", frame);
    std::string line = name + std::string(name.size() < 30 ? 30 - name.size() : 0, ' ') + head +
                       board_->name + ": ";
    if (!pose) return line + "not seen\n";
    char body[256];
    std::snprintf(body, sizeof body,
                  "t = (%g, %g, %g) m  %zu of %zu tags  rms %.2f px  ambiguity %.2f", pose->tvec[0],
                  pose->tvec[1], pose->tvec[2], pose->tags_used.size(), board_->tags.size(),
                  pose->rms_error_px, pose->ambiguity);
    line += body;
    if (!pose->detections_rejected.empty()) {
      line += "  left out: ID";
      for (int i : pose->detections_rejected) line += " " + std::to_string(detections[i].id);
    }
    return line + "\n";
  }

  // The drawn axes: twice the board's largest tag.
  double BoardAxis() const {
    double size = 0;
    for (const BoardTag& tag : board_->tags) size = std::max(size, tag.size);
    return 2.0 * size;
  }

  const DetectOptions& options_;
  const Detector& detector_;
  const cv::Size camera_size_;  // The camera file's recorded image size, if any.
  mutable std::mutex scaled_mutex_;
  // Detectors for frame sizes other than the camera file's; null: not scaled.
  mutable std::map<std::pair<int, int>, std::unique_ptr<Detector>> scaled_;
  const std::optional<Board>& board_;
  const std::vector<Source> sources_;
  const int jobs_;
  const size_t capacity_;
  std::atomic<size_t> total_{0};
  // The reader's: frames read so far, and whether a limit ended the reading.
  std::chrono::steady_clock::time_point started_;  // When reading starts.
  int64_t frames_read_ = 0;
  std::atomic<bool> limit_reached_{false};
  std::string limit_;  // Written by the reader before it sets read_all_.

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
};

int RunDetect(const DetectOptions& options) {
  // From the start: a signal while the detector is set up still ends with a
  // summary.
  g_stop = false;
  g_stop_now = false;
  g_end_after_writes = false;
  g_signal = 0;
  for (int s : kEndingSignals) std::signal(s, OnSignal);
  const auto fail = [](const std::string& message) { return Fail("detect", message); };
  DetectorOptions detector_options;
  detector_options.families =
      options.family == "all" ? TagFamily::Names() : std::vector<std::string>{options.family};
  detector_options.report_rejected = options.rejected;
  std::string error;
  if (!options.config.empty() && !LoadDetectorConfig(options.config, &detector_options, &error))
    return fail(error);
  CameraFileInfo camera_info;
  if (!options.camera_file.empty()) {
    CameraIntrinsics camera;
    if (!LoadCameraFile(options.camera_file, &camera, &error, &camera_info)) return fail(error);
    detector_options.camera = camera;
  }
  if (!options.tag_size.empty()) {
    const auto length = ParseLength(options.tag_size, &error);
    if (!length) return fail("--tag-size: " + error);
    detector_options.tag_size = length->mm / 1000.0;
  }
  std::optional<Board> board;
  if (!options.board_file.empty()) {
    board = ReadBoardFile(options.board_file, &error);
    if (!board) return fail(error);
    if (!detector_options.camera) return fail("--board needs --camera FILE (the intrinsics)");
    // The board's families only, unless --family says otherwise; a --family
    // that leaves the board's out would never see it.
    std::vector<std::string> families;
    for (const BoardTag& tag : board->tags) {
      if (std::find(families.begin(), families.end(), tag.family) == families.end())
        families.push_back(tag.family);
    }
    if (options.family == "all") {
      detector_options.families = families;
    } else if (std::find(families.begin(), families.end(), options.family) == families.end()) {
      return fail("--family " + options.family + " leaves out every tag of the board (" +
                  families[0] + (families.size() > 1 ? " and " + families[1] : "") + ")");
    }
  }
  if (detector_options.tag_size > 0 && !detector_options.camera)
    return fail("pose needs both --camera FILE and --tag-size LENGTH");
  if (detector_options.camera && !(detector_options.tag_size > 0) && !board)
    return fail("pose needs both --camera FILE and --tag-size LENGTH (or --board FILE)");
  if (options.show && !std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY"))
    return fail("--show needs a display (neither DISPLAY nor WAYLAND_DISPLAY is set)");
  std::vector<Source> sources;
  std::vector<std::string> notes, skipped;
  if (!GatherSources(options.inputs, options.camera_indices, &sources, &error, &notes, &skipped))
    return fail(error);
  for (const std::string& note : notes) Fail("detect", note, kExitOk);
  for (const std::string& entry : skipped) Fail("detect", entry, kExitOk);
  if (!options.overlay_dir.empty()) {
    std::error_code ec;
    fs::create_directories(options.overlay_dir, ec);
    if (ec)
      return fail("cannot create overlay folder '" + options.overlay_dir + "': " + ec.message());
  }
  auto detector = Detector::Create(detector_options, &error);
  if (!detector) return fail(error);
  const int jobs = options.jobs > 0
                       ? options.jobs
                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Run run(options, *detector, board, std::move(sources), jobs, camera_info.image_size);
  int code = run.Execute();
  if (!skipped.empty() && code == kExitOk) code = kExitFailure;  // An input was not read.
  if (g_signal) DieBy(g_signal);
  for (int s : kEndingSignals) std::signal(s, SIG_DFL);
  return code;
}

}  // namespace

void RegisterDetect(CLI::App& app, Action* action) {
  auto options = std::make_shared<DetectOptions>();
  CLI::App* command = app.add_subcommand(
      "detect", "Detect ChromaTags in images, folders, videos, cameras and streams");
  command
      ->add_option("--family", options->family,
                   "Tag family: 16h5, 36h11 or all (both; no measurable cost, docs/live.md)")
      ->capture_default_str()
      ->transform(FamilyPrefix())
      ->check(CLI::IsMember({"16h5", "36h11", "all"}));
  command->add_flag("--json", options->json,
                    "One JSON object per frame per line (video and live frames with a timestamp)");
  command->add_option("--overlay", options->overlay_dir,
                      "Write each frame with the detections drawn into this folder "
                      "(<file>_<ext>[_<frame>].png)");
  command->add_option("--camera", options->camera_file,
                      "Camera intrinsics for pose: OpenCV YAML/JSON/XML (camera_matrix, "
                      "distortion_coefficients), ROS camera_info YAML or Kalibr camchain YAML");
  command->add_option("--tag-size", options->tag_size,
                      "Side of the black square, e.g. 40mm, for pose");
  command->add_option("--board", options->board_file,
                      "Report the pose of this board or bundle per frame (with --camera): a "
                      "sheet (or its sidecar .json) or a bundle YAML (FILE[#NAME]); docs/pose.md");
  command->add_option("--config", options->config,
                      "Detector config JSON (thresholds from 'chromatag calibrate')");
  command->add_flag("--rejected", options->rejected,
                    "Also report the rejected candidates (JSON: \"rejected\") and draw them on "
                    "the overlays, coloured by the stage that rejected them");
  command->add_option("--camera-index", options->camera_indices,
                      "Read a camera by its index (as /dev/videoN); repeatable");
  command->add_flag("--show", options->show,
                    "Show the frames with the detections in a window (q quits)");
  command
      ->add_option("--open-timeout", options->open_timeout_s,
                   "Seconds a stream's server may take to answer before it is given up")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 3600.0));
  command
      ->add_option("--max-frames", options->max_frames,
                   "End after this many frames read (images and video frames over all inputs, "
                   "dropped live frames included)")
      ->check(CLI::Range(int64_t{1}, int64_t{1} << 40));
  command
      ->add_option("--duration", options->duration_s,
                   "End the reading this many seconds after it starts (frames under way are "
                   "finished)")
      ->check(CLI::Range(1e-3, 1e9));
  command->add_flag("--every-frame", options->every_frame,
                    "Cameras and streams: detect in every frame, however late, instead of "
                    "dropping frames a newer one has overtaken");
  command
      ->add_option("-j,--jobs", options->jobs,
                   "Threads that decode and detect (default: one per core)")
      ->check(CLI::Range(1, 256));
  command->add_option(
      "INPUT", options->inputs,
      "Images, folders, videos, /dev/videoN or stream URLs (rtsp://, http://, ...); "
      "Ctrl-C, SIGTERM, SIGHUP or SIGQUIT ends a run with its summary (a second one without "
      "waiting for frames "
      "under way)");
  command->callback([options, action] { *action = [options] { return RunDetect(*options); }; });
}

}  // namespace chromatag::cli
