#include "detect_run.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <thread>

#include <opencv2/highgui.hpp>
#include <opencv2/videoio.hpp>

#include "chromatag/detector/detection_json.h"
#include "chromatag/detector/read_image.h"
#include "commands.h"
#include "detect_output.h"
#include "detect_signals.h"
#include "flag_terms.h"
#include "library_output.h"

namespace chromatag::cli {
namespace {

// How often waits look at the signal flags.
constexpr std::chrono::milliseconds kPoll(50);
// How long, after Ctrl-C, every frame read so far is printed and the reader
// has still not come back (a stream that stalled in its open or a read),
// before the run ends without it.
constexpr std::chrono::milliseconds kReaderGrace(1000);

}  // namespace

int Run::Execute() {
  bool live = false;
  size_t images = 0;
  for (const Source& s : sources_) {
    live |= s.live();
    images += s.kind == SourceKind::kImage ? 1 : 0;
  }
  total_ = images;
  Progress progress("detect", "frames", live ? 0 : total_.load());
  start_ = std::chrono::steady_clock::now();
  std::thread reader([this] { Read(); });
  std::vector<std::thread> workers;
  for (int i = 0; i < jobs_; ++i) workers.emplace_back([this] { Work(); });
  if (!options_.json) std::cout << kTableHeading;
  Tally tally;
  PrintInOrder(live, &progress, &tally);
  if (g_stop_now || tally.reader_stuck) {
    // A second signal, or a reader stuck in a stalled stream after the
    // first: the reader (and after a second signal the workers) cannot be
    // waited for. The printed lines are whole, the summary says how many,
    // and the process ends here. Overlays are written through temporary
    // files, so none is left half-written.
    EndWithoutThreads(Summary(tally, &progress));
  }
  reader.join();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& w : workers) w.join();
  return Summary(tally, &progress);
}

void Run::PrintInOrder(bool live, Progress* progress, Tally* tally) {
  for (size_t next = 0; !g_stop_now; ++next) {
    std::optional<Outcome> outcome = Next(next, tally);
    if (!outcome) break;
    if (outcome->dropped) {
      ++tally->dropped;
      continue;
    }
    PrintOutcome(*outcome, live, progress, tally);
  }
}

std::optional<Outcome> Run::Next(size_t next, Tally* tally) {
  std::optional<Outcome> outcome;
  {
    // Polled: a signal handler cannot wake a condition variable.
    std::unique_lock<std::mutex> lock(mutex_);
    const auto ready = [&] { return done_.count(next) || (read_all_ && next == queued_); };
    // Stopped (a signal, or --duration over), every frame read printed for
    // kReaderGrace, and the reader still in a read (or an open) that does
    // not return. Nothing is queued after that (abandoned_).
    const auto stuck = [&] {
      const auto now = std::chrono::steady_clock::now();
      tally->duration_over =
          options_.duration_s > 0 &&
          std::chrono::duration<double>(now - start_).count() >= options_.duration_s;
      if (!(g_stop || tally->duration_over) || next != queued_) {
        stop_seen_ = std::chrono::steady_clock::time_point();
        return false;
      }
      if (stop_seen_ == std::chrono::steady_clock::time_point()) stop_seen_ = now;
      return abandoned_ = now - stop_seen_ >= kReaderGrace;
    };
    while (!ready() && !g_stop_now && !(tally->reader_stuck = stuck()))
      done_changed_.wait_for(lock, kPoll);
    if (!done_.count(next)) return std::nullopt;
    outcome = std::move(done_[next]);
    done_.erase(next);
    if (outcome->dropped) --dropped_pending_;
  }
  space_.notify_all();
  return outcome;
}

void Run::WriteSmoothed(Outcome* outcome) {
  PendingFrame& p = *outcome->pending;
  const double time_s = p.record.timestamp.value_or(0.0);  // Videos and cameras have one.
  for (Detection& d : p.detections) {
    if (!d.has_pose) continue;
    const FilteredPose f = tag_filters_[{p.source, d.family->name(), d.id}].Update(
        time_s, d.pose.rvec, d.pose.tvec, d.pose.covariance);
    d.pose.rvec = f.rvec;
    d.pose.tvec = f.tvec;
    d.pose.covariance = f.covariance;
  }
  if (p.board_pose) {
    const FilteredPose f = board_filters_[p.source].Update(
        time_s, p.board_pose->rvec, p.board_pose->tvec, p.board_pose->covariance);
    p.board_pose->rvec = f.rvec;
    p.board_pose->tvec = f.tvec;
    p.board_pose->covariance = f.covariance;
  }
  outcome->out = FrameText(p.record, p.detections, p.board_pose, p.rejected);
  outcome->pending.reset();
}

void Run::PrintOutcome(Outcome& outcome, bool live, Progress* progress, Tally* tally) {
  if (outcome.pending) WriteSmoothed(&outcome);
  std::cout << outcome.out << std::flush;
  if (!outcome.err.empty()) {
    progress->Finish();  // The message on a line of its own; the bar comes back.
    std::cerr << outcome.err;
  }
  tally->failed |= outcome.failed;
  if (outcome.frame) {
    ++tally->frames;
    tally->with_tags += outcome.tags > 0 ? 1 : 0;
    tally->tags += static_cast<size_t>(outcome.tags);
  }
  if (!live) progress->set_total(total_);
  progress->Update(tally->frames);
  if (options_.show && !outcome.shown.empty()) {
    cv::imshow("chromatag detect", outcome.shown);
    const int key = cv::waitKey(1);
    if (key == 'q' || key == 27) g_stop = true;
  }
}

int Run::Summary(const Tally& tally, Progress* progress) {
  progress->Finish();
  std::cout.flush();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string ended = g_signal         ? " (interrupted)"
                      : limit_reached_ ? " (" + limit_ + ")"
                      : tally.reader_stuck && tally.duration_over
                          ? " (--duration, the stream stalled)"
                          : "";
  if (tally.dropped) ended += ", " + std::to_string(tally.dropped) + " stale live frames dropped";
  const size_t frames = tally.frames;
  std::fprintf(ToolErr(),
               "detect: %zu frame%s, %zu with tags, %zu tag%s in %.2f s: %.1f frames/s on %d "
               "thread%s%s\n",
               frames, frames == 1 ? "" : "s", tally.with_tags, tally.tags,
               tally.tags == 1 ? "" : "s", seconds,
               seconds > 0 ? static_cast<double>(frames) / seconds : 0.0, jobs_,
               jobs_ == 1 ? "" : "s", ended.c_str());
  std::fflush(ToolErr());
  return tally.failed ? kExitFailure : kExitOk;
}

void Run::EndWithoutThreads(int code) {
  // A worker writing an overlay has signals blocked in its thread, but the
  // process would die around it: let the write end (a PNG takes
  // milliseconds; a stuck disk is not waited for past two seconds).
  dying_ = true;
  for (int i = 0; writing_ > 0 && i < 200; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (g_signal) DieBy(g_signal);
  std::_Exit(code);  // Stopped from the --show window.
}

// Queues a task in order, waiting while `capacity_` frames are under way. A
// live frame instead replaces the frames of its source still waiting for a
// worker (they are stale now; each is reported as dropped), unless
// --every-frame.
void Run::Queue(Task task) {
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

bool Run::LimitReached() {
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

void Run::Read() {
  started_ = std::chrono::steady_clock::now();
  for (size_t i = 0; i < sources_.size() && !g_stop && !LimitReached(); ++i) {
    if (sources_[i].kind == SourceKind::kImage) {
      ++frames_read_;
      Queue({i, 0, {}, 0, {}});
      continue;
    }
    ReadVideo(i);
  }
  std::lock_guard<std::mutex> lock(mutex_);
  read_all_ = true;
  done_changed_.notify_all();
}

// A video, a camera or a stream: its frames, or why it gives none.
void Run::ReadVideo(size_t i) {
  const Source& source = sources_[i];
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
    const char* what = source.kind == SourceKind::kVideo ? "video"
                       : source.live()                   ? "camera or stream"
                                                         : "";
    Queue(
        {i,
         0,
         {},
         0,
         std::string("cannot open ") + what + " '" + source.name + "'" + timed_out + ", skipped"});
    return;
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
    // Live: when the frame arrived (seconds since the epoch); a video file:
    // the frame's place in it (seconds from its start).
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

void Run::Work() {
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

Outcome Run::Process(Task& task, DetectionResult* result) const {
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
  const Detector& detector = detectors_.For(frame.size(), &outcome.err);
  detector.Detect(frame, PixelOrder::kBgr, result);
  outcome.frame = true;
  outcome.tags = static_cast<int>(result->detections.size());
  const DetectorOptions& d = detector.options();
  const std::optional<BoardPose> board_pose = BoardPoseIn(source, task, *result, d, &outcome);
  std::string overlay;
  if (!options_.overlay_dir.empty() || options_.show)
    overlay = Draw(source, task, *result, d, board_pose, &outcome);
  const FrameJsonRecord record = RecordOf(source, task, *result, overlay);
  if (options_.smooth) {
    // The printer filters the poses in frame order, then writes the frame.
    outcome.pending =
        PendingFrame{task.source, record, result->detections, board_pose,
                     options_.rejected ? result->rejected : std::vector<RejectedCandidate>()};
    return outcome;
  }
  outcome.out = FrameText(record, result->detections, board_pose, result->rejected);
  return outcome;
}

FrameJsonRecord Run::RecordOf(const Source& source, const Task& task, const DetectionResult& result,
                              const std::string& overlay) const {
  FrameJsonRecord record;
  record.file = source.name;
  record.frame = task.frame_index;
  record.width = task.frame.cols;
  record.height = task.frame.rows;
  record.time_us = result.summary.total_time_us;
  if (source.kind != SourceKind::kImage) record.timestamp = task.timestamp;
  record.overlay = overlay;
  return record;
}

std::string Run::FrameText(FrameJsonRecord record, const std::vector<Detection>& detections,
                           const std::optional<BoardPose>& board_pose,
                           const std::vector<RejectedCandidate>& rejected) const {
  const Board* board = board_ ? &*board_ : nullptr;
  if (!options_.json) return TableLines(record.file, record.frame, detections, board, board_pose);
  record.board = board;
  record.board_pose = board_pose ? &*board_pose : nullptr;
  record.rejected = options_.rejected ? &rejected : nullptr;
  return FrameJson(record, detections) + "\n";
}

std::optional<BoardPose> Run::BoardPoseIn(const Source& source, const Task& task,
                                          const DetectionResult& result,
                                          const DetectorOptions& options, Outcome* outcome) const {
  if (!board_) return std::nullopt;
  // A board tag seen twice in one frame: a frame spliced from two (a video
  // cut mid-frame) or two boards in view. Its pose is not reported, and the
  // frame is named.
  std::map<std::pair<std::string, int>, int> seen;
  std::string twice;
  for (const Detection& det : result.detections) {
    if (board_->Find(det.family->name(), det.id) >= 0 && ++seen[{det.family->name(), det.id}] == 2)
      twice += (twice.empty() ? "" : ", ") + std::to_string(det.id);
  }
  if (!twice.empty()) {
    outcome->err += "chromatag detect: '" + source.name + "' frame " +
                    std::to_string(task.frame_index) + ": board tag(s) " + twice +
                    " seen twice (a damaged or spliced frame, or two boards in view): no board "
                    "pose, skipped\n";
    outcome->failed = true;
    return std::nullopt;
  }
  BoardPose pose;
  if (!EstimateBoardPose(result.detections, *board_, *options.camera, &pose)) return std::nullopt;
  return pose;
}

std::string Run::Draw(const Source& source, const Task& task, const DetectionResult& result,
                      const DetectorOptions& options, const std::optional<BoardPose>& board_pose,
                      Outcome* outcome) const {
  const cv::Mat canvas = DrawFrame(task.frame, result, options, options_.rejected,
                                   board_ ? &*board_ : nullptr, board_pose);
  if (options_.show) outcome->shown = canvas;
  if (options_.overlay_dir.empty()) return "";
  const std::string overlay = OverlayPath(options_.overlay_dir, source, task.frame_index);
  std::string why;
  if (WriteOverlay(canvas, overlay, dying_, &writing_, &why)) return overlay;
  outcome->err = "chromatag detect: cannot write overlay '" + overlay + "'" +
                 (why.empty() ? "" : ": " + why) + "\n";
  outcome->failed = true;
  return "";
}

}  // namespace chromatag::cli
