// `chromatag detect` on videos and streams: frames in order on any number of
// threads, overlay names that cannot collide, timestamps, frame and time
// limits, and Ctrl-C or SIGTERM ending a run cleanly with its summary.
#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "chromatag/generator/tag_renderer.h"
#include "test_util.h"

namespace chromatag {
namespace {

namespace fs = std::filesystem;
using testing::CountLines;
constexpr auto Chromatag = testing::RunChromatag;

// An MJPG clip of `frames` frames with 16h5 ID 3 sliding across a grey frame.
std::string MakeClip(const std::string& dir, const std::string& name, int frames) {
  const auto family = TagFamily::Load("16h5");
  const RgbImage tag =
      RasterizeTag(*family, 3, TagColors::FromPalette(*BuiltinPalette("default")), 6);
  const cv::Mat rgb(tag.height, tag.width, CV_8UC3, const_cast<uint8_t*>(tag.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  const std::string path = dir + "/" + name;
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30, cv::Size(240, 180));
  EXPECT_TRUE(writer.isOpened());
  for (int i = 0; i < frames; ++i) {
    cv::Mat frame(180, 240, CV_8UC3, cv::Scalar(110, 110, 110));
    bgr.copyTo(frame(cv::Rect(10 + i % 120, 40, bgr.cols, bgr.rows)));
    writer.write(frame);
  }
  return path;
}

// The folders FreshDir made in this process (ctest runs each test in its
// own); removed when every test passed, kept to look into when one failed.
std::vector<std::string>& MadeDirs() {
  static std::vector<std::string> dirs;
  return dirs;
}

class RemoveMadeDirs : public ::testing::Environment {
 public:
  void TearDown() override {
    if (!::testing::UnitTest::GetInstance()->Passed()) return;
    for (const std::string& dir : MadeDirs()) fs::remove_all(dir);
  }
};
::testing::Environment* const kRemoveMadeDirs =
    ::testing::AddGlobalTestEnvironment(new RemoveMadeDirs);

std::string FreshDir(const std::string& name) {
  const std::string dir =
      ::testing::TempDir() + "/cli_live_" + std::to_string(getpid()) + "_" + name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  MadeDirs().push_back(dir);
  return dir;
}

std::vector<nlohmann::json> JsonLines(const std::string& text) {
  std::vector<nlohmann::json> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

TEST(CliLiveTest, FramesComeInInputOrderOnAnyNumberOfThreads) {
  const std::string dir = FreshDir("order");
  const std::string clip = MakeClip(dir, "clip.avi", 60);
  cv::imwrite(dir + "/clip.png", cv::Mat(100, 100, CV_8UC3, cv::Scalar(90, 90, 90)));
  std::string reference;
  for (const char* jobs : {"1", "4"}) {
    const auto run = Chromatag({"detect", "--json", "-j", jobs, clip, dir + "/clip.png", clip});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto lines = JsonLines(run.out);
    ASSERT_EQ(lines.size(), 121u);
    for (int i = 0; i < 121; ++i) {
      const int expected = i < 60 ? i : i == 60 ? 0 : i - 61;
      EXPECT_EQ(lines[i]["frame"], expected) << i;
      EXPECT_EQ(lines[i]["detections"].size(), i == 60 ? 0u : 1u) << i;
    }
    EXPECT_NE(run.err.find("121 frames, 120 with tags, 120 tags"), std::string::npos) << run.err;
    std::string ids;
    for (const auto& line : lines)
      for (const auto& d : line["detections"]) ids += d["corners"].dump();
    if (reference.empty()) reference = ids;
    EXPECT_EQ(ids, reference) << "the same corners on " << jobs << " threads";
  }
}

// An image and a video of the same stem, and two files of one name in two
// folders, each keep their own overlays (the video's frame 0 used to
// overwrite the image's).
TEST(CliLiveTest, OverlayNamesAreUniquePerInput) {
  const std::string dir = FreshDir("overlays");
  fs::create_directories(dir + "/a");
  fs::create_directories(dir + "/b");
  MakeClip(dir, "scene.avi", 2);
  const cv::Mat grey(80, 80, CV_8UC3, cv::Scalar(90, 90, 90));
  cv::imwrite(dir + "/scene.png", grey);
  cv::imwrite(dir + "/a/x.png", grey);
  cv::imwrite(dir + "/b/x.png", grey);
  const auto run = Chromatag({"detect", "--json", "--overlay", dir + "/out", dir + "/scene.png",
                              dir + "/scene.avi", dir + "/a/x.png", dir + "/b/x.png"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir + "/out"))
    names.insert(entry.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"scene_png.png", "scene_avi_000000.png",
                                          "scene_avi_000001.png", "x_png.png", "x_png-2.png"}));
  for (const auto& line : JsonLines(run.out))
    EXPECT_TRUE(fs::exists(line["overlay"].get<std::string>())) << line.dump();
}

TEST(CliLiveTest, StreamsCarryTimestamps) {
  const std::string dir = FreshDir("stream");
  const std::string clip = MakeClip(dir, "clip.avi", 20);
  const double before = static_cast<double>(time(nullptr));
  // Every frame: a stream read faster than it is detected would drop some.
  const auto run = Chromatag({"detect", "--json", "--every-frame", "file://" + clip});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto lines = JsonLines(run.out);
  ASSERT_EQ(lines.size(), 20u);
  double last = 0;
  for (const auto& line : lines) {
    const double t = line["timestamp"].get<double>();
    EXPECT_GE(t, before - 1);
    EXPECT_GE(t, last);
    last = t;
  }
  // A video file's frames carry their place in it: 30 frames a second.
  const auto file_lines = JsonLines(Chromatag({"detect", "--json", clip}).out);
  ASSERT_EQ(file_lines.size(), 20u);
  for (size_t i = 0; i < file_lines.size(); ++i)
    EXPECT_NEAR(file_lines[i]["timestamp"].get<double>(), i / 30.0, 1e-6);
}

// A live source detects the newest frame: frames a newer one overtook
// while they waited are dropped, counted in the summary, and never printed.
TEST(CliLiveTest, LiveSourcesDropStaleFrames) {
  const std::string dir = FreshDir("stale");
  const std::string clip = MakeClip(dir, "clip.avi", 400);
  const auto run = Chromatag({"detect", "--json", "-j", "1", "file://" + clip});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto lines = JsonLines(run.out);
  // Every frame is printed or counted as dropped.
  size_t dropped = 0;
  const size_t at = run.err.find(" stale live frames dropped");
  if (at != std::string::npos) {
    const size_t start = run.err.rfind(", ", at) + 2;
    dropped = std::stoul(run.err.substr(start, at - start));
  }
  EXPECT_EQ(lines.size() + dropped, 400u) << run.err;
  for (size_t i = 1; i < lines.size(); ++i)
    EXPECT_GT(lines[i]["frame"].get<int>(), lines[i - 1]["frame"].get<int>());
  const auto every = Chromatag({"detect", "--json", "-j", "1", "--every-frame", "file://" + clip});
  EXPECT_EQ(JsonLines(every.out).size(), 400u);
  EXPECT_EQ(every.err.find("dropped"), std::string::npos) << every.err;
}

// --max-frames and --duration end a run, and the summary says which.
TEST(CliLiveTest, FrameAndTimeLimitsEndARun) {
  const std::string dir = FreshDir("limits");
  const std::string clip = MakeClip(dir, "clip.avi", 20);
  const auto frames = Chromatag({"detect", "--json", "--max-frames", "7", clip, clip});
  ASSERT_EQ(frames.exit_code, 0) << frames.err;
  EXPECT_EQ(JsonLines(frames.out).size(), 7u);
  EXPECT_NE(frames.err.find("(--max-frames 7)"), std::string::npos) << frames.err;
  const std::string long_clip = MakeClip(dir, "long.avi", 3000);
  const auto timed = Chromatag({"detect", "--json", "--duration", "0.05", long_clip});
  ASSERT_EQ(timed.exit_code, 0) << timed.err;
  EXPECT_LT(JsonLines(timed.out).size(), 3000u);
  EXPECT_NE(timed.err.find("(--duration 0.05 s)"), std::string::npos) << timed.err;
  const auto zero = Chromatag({"detect", "--max-frames", "0", clip});
  EXPECT_EQ(zero.exit_code, 2);
}

// `chromatag detect --json URL`, sent `signals` once `ready(stdout so far)`
// says so; what it printed, how it ended and how long after the signals.
struct SignalledRun {
  std::string out, err;
  int status = 0;
  bool signalled = false, ended = false;
  std::chrono::steady_clock::duration after_signals{}, total{};
};

SignalledRun RunAndSignal(const std::string& dir, const std::vector<std::string>& args,
                          const std::vector<int>& signals,
                          const std::function<bool(const std::string&)>& ready) {
  SignalledRun run;
  std::vector<const char*> argv = {CHROMATAG_CLI_PATH, "detect", "--json"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  argv.push_back(nullptr);
  const std::string err_path = dir + "/stderr.txt";
  int out_pipe[2];
  EXPECT_EQ(pipe(out_pipe), 0);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out_pipe[1], STDOUT_FILENO);
    const int err = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(err, STDERR_FILENO);
    close(out_pipe[0]);
    execv(CHROMATAG_CLI_PATH, const_cast<char* const*>(argv.data()));
    _exit(127);
  }
  close(out_pipe[1]);
  fcntl(out_pipe[0], F_SETFL, O_NONBLOCK);
  char buffer[65536];
  const auto drain = [&] {
    for (ssize_t n; (n = read(out_pipe[0], buffer, sizeof buffer)) > 0;)
      run.out.append(buffer, static_cast<size_t>(n));
  };
  const auto start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point signalled_at;
  while (std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
    if (waitpid(pid, &run.status, WNOHANG) == pid) {
      run.ended = true;
      break;
    }
    drain();
    if (!run.signalled && ready(run.out)) {
      // A couple of milliseconds apart, as keys pressed in quick succession.
      for (int signal : signals) {
        kill(pid, signal);
        usleep(2000);
      }
      run.signalled = true;
      signalled_at = std::chrono::steady_clock::now();
    }
    usleep(10000);
  }
  if (!run.ended) {
    kill(pid, SIGKILL);
    waitpid(pid, &run.status, 0);
  }
  drain();
  close(out_pipe[0]);
  run.after_signals = std::chrono::steady_clock::now() - signalled_at;
  run.total = std::chrono::steady_clock::now() - start;
  run.err = testing::ReadFile(err_path);
  return run;
}

// Ended by the last signal, every line whole, and the summary counting them.
void ExpectEndedCleanly(const SignalledRun& run, const std::vector<int>& signals) {
  ASSERT_TRUE(run.ended) << "still running 60 s after it started; " << run.err;
  ASSERT_TRUE(run.signalled) << run.err;
  ASSERT_TRUE(WIFSIGNALED(run.status)) << "exit " << WEXITSTATUS(run.status) << ": " << run.err;
  EXPECT_EQ(WTERMSIG(run.status), signals.back());
  const auto lines = JsonLines(run.out);  // Throws on a half-written line.
  EXPECT_GE(lines.size(), 1u);
  EXPECT_NE(run.err.find("(interrupted)"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("detect: " + std::to_string(lines.size()) + " frame"), std::string::npos)
      << run.err;
}

// A live run ended by Ctrl-C, by Ctrl-C twice (the second without waiting
// for frames under way), by SIGTERM, SIGHUP or SIGQUIT: every line written
// is whole, the
// summary counts them and says it was interrupted, and the process ends by
// the signal, so that a shell (a loop over files) knows.
class CliLiveSignalTest : public ::testing::TestWithParam<std::vector<int>> {};

TEST_P(CliLiveSignalTest, EndsALiveRunCleanly) {
  const std::vector<int> signals = GetParam();
  const std::string dir =
      FreshDir("signal" + std::to_string(signals.size()) + std::to_string(signals[0]));
  const std::string clip = MakeClip(dir, "long.avi", 3000);
  const SignalledRun run =
      RunAndSignal(dir, {"-j", "1", "file://" + clip}, signals,
                   [](const std::string& out) { return out.find('\n') != std::string::npos; });
  ExpectEndedCleanly(run, signals);
  EXPECT_LT(JsonLines(run.out).size(), 3000u);
}

INSTANTIATE_TEST_SUITE_P(Signals, CliLiveSignalTest,
                         ::testing::Values(std::vector<int>{SIGINT},
                                           std::vector<int>{SIGINT, SIGINT},
                                           std::vector<int>{SIGTERM}, std::vector<int>{SIGHUP},
                                           std::vector<int>{SIGQUIT}));

// Two SIGTERMs (or SIGHUPs, or SIGQUITs) while overlays are being written
// (the second ends the run without waiting for the workers), or three
// SIGINTs (the third ends the process): a write under way ends first, none
// starts after, and no temporary file is left, run after run.
TEST(CliLiveTest, NoOverlayTemporaryIsLeftBySignals) {
  const std::string dir = FreshDir("overlay_signals");
  const std::string clip = MakeClip(dir, "clip.avi", 3000);
  // Measured with the clip of this test's kind, 20 runs each: three SIGINTs
  // 2 ms apart left temporaries in 3 runs before the third signal waited
  // for writes under way, in none after.
  for (int run_index = 0; run_index < 14; ++run_index) {
    const std::string overlays = dir + "/o" + std::to_string(run_index);
    const int signal = run_index % 3 == 0 ? SIGTERM : run_index % 3 == 1 ? SIGHUP : SIGQUIT;
    // The last eight: three SIGINTs, the third of which ends the process as
    // soon as no overlay is being written.
    const std::vector<int> signals =
        run_index < 6 ? std::vector<int>{signal, signal} : std::vector<int>{SIGINT, SIGINT, SIGINT};
    const SignalledRun run = RunAndSignal(
        dir, {"--jobs", "2", "--overlay", overlays, clip}, signals,
        [](const std::string& out) { return std::count(out.begin(), out.end(), '\n') >= 3; });
    ASSERT_TRUE(run.ended && run.signalled) << run.err;
    JsonLines(run.out);  // Whole lines.
    for (const auto& entry : fs::directory_iterator(overlays))
      EXPECT_NE(entry.path().filename().string().rfind(".chromatag", 0), 0u) << entry.path();
  }
}

// A stream that stalls: a loopback TCP server sends JPEG frames (FFmpeg
// reads them as a JPEG pipe), then keeps the connection open and sends
// nothing, so the reader blocks in a read that does not return. Ctrl-C (once
// or twice) and SIGTERM still end the run within seconds, with every line
// whole and the summary.
class StalledStream {
 public:
  explicit StalledStream(int frames) {
    listener_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    socklen_t length = sizeof address;
    getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length);
    port_ = ntohs(address.sin_port);
    EXPECT_EQ(listen(listener_, 1), 0);
    // Noise makes each JPEG large, so that FFmpeg's probe (5 MB) ends.
    const auto family = TagFamily::Load("16h5");
    const RgbImage tag =
        RasterizeTag(*family, 3, TagColors::FromPalette(*BuiltinPalette("default")), 8);
    cv::Mat rgb(tag.height, tag.width, CV_8UC3, const_cast<uint8_t*>(tag.pixels.data())), frame;
    cv::Mat noise(480, 640, CV_8UC3);
    cv::randu(noise, cv::Scalar::all(60), cv::Scalar::all(200));
    cv::cvtColor(rgb, frame, cv::COLOR_RGB2BGR);
    frame.copyTo(noise(cv::Rect(40, 30, frame.cols, frame.rows)));
    cv::imencode(".jpg", noise, jpeg_);
    server_ = std::thread([this, frames] {
      client_ = accept(listener_, nullptr, nullptr);
      for (int i = 0; i < frames && client_ >= 0; ++i)
        if (send(client_, jpeg_.data(), jpeg_.size(), MSG_NOSIGNAL) < 0) break;
      sent_ = true;
    });
  }
  ~StalledStream() {
    shutdown(listener_, SHUT_RDWR);
    close(listener_);
    server_.join();
    if (client_ >= 0) close(client_);
  }
  std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port_); }
  bool sent() const { return sent_; }

 private:
  int listener_ = -1;
  std::atomic<int> client_{-1};
  int port_ = 0;
  std::vector<uchar> jpeg_;
  std::atomic<bool> sent_{false};
  std::thread server_;
};

class CliStalledStreamTest : public ::testing::TestWithParam<std::vector<int>> {};

TEST_P(CliStalledStreamTest, EndsWhenTheStreamStalls) {
  const std::vector<int> signals = GetParam();
  const std::string dir =
      FreshDir("stalled" + std::to_string(signals.size()) + std::to_string(signals[0]));
  StalledStream stream(60);
  // Signalled once every frame is sent, some are printed, and the output
  // has been silent for two seconds: the reader is blocked in its read.
  size_t last_size = 0;
  auto quiet_since = std::chrono::steady_clock::now();
  const SignalledRun run = RunAndSignal(dir, {stream.url()}, signals, [&](const std::string& out) {
    const auto now = std::chrono::steady_clock::now();
    if (out.size() != last_size) {
      last_size = out.size();
      quiet_since = now;
    }
    return stream.sent() && out.find('\n') != std::string::npos &&
           now - quiet_since > std::chrono::seconds(2);
  });
  ExpectEndedCleanly(run, signals);
  // Within the reader's grace (1 s) and a margin, not FFmpeg's own timeouts;
  // after one signal, not before the grace: the reader was stuck.
  EXPECT_LT(run.after_signals, std::chrono::seconds(5));
  if (signals.size() == 1) {
    EXPECT_GE(run.after_signals, std::chrono::milliseconds(900));
  }
}

// --duration ends a run whose stream has stalled, too: the reader never
// comes back to look at the clock.
TEST(CliLiveTest, DurationEndsAStalledStream) {
  const std::string dir = FreshDir("stalled_duration");
  // 25 frames (7 MB: past FFmpeg's 5 MB probe), read well within the 6 s
  // even on a loaded machine; the rest of the 6 s the stream is silent.
  StalledStream stream(25);
  const SignalledRun run = RunAndSignal(dir, {"--duration", "6", stream.url()}, {},
                                        [](const std::string&) { return false; });
  ASSERT_TRUE(run.ended) << run.err;
  ASSERT_TRUE(WIFEXITED(run.status)) << run.err;
  EXPECT_EQ(WEXITSTATUS(run.status), 0) << run.err;
  EXPECT_GE(JsonLines(run.out).size(), 1u);
  EXPECT_NE(run.err.find("(--duration, the stream stalled)"), std::string::npos) << run.err;
  // 6 s and the reader's grace, not FFmpeg's own 30 s timeout.
  EXPECT_LT(run.total, std::chrono::seconds(18));
}

// A server that accepts and never answers is given up after --open-timeout
// (FFmpeg alone waits 30 s or more), named, and the run ends: exit 1.
TEST(CliLiveTest, OpenTimeoutEndsASilentServer) {
  const std::string dir = FreshDir("silent");
  StalledStream silent(0);
  const SignalledRun run = RunAndSignal(dir, {"--open-timeout", "1.5", silent.url()}, {},
                                        [](const std::string&) { return false; });
  ASSERT_TRUE(run.ended) << run.err;
  ASSERT_TRUE(WIFEXITED(run.status)) << run.err;
  EXPECT_EQ(WEXITSTATUS(run.status), 1) << run.err;
  EXPECT_NE(run.err.find("cannot open camera or stream '" + silent.url() +
                         "' (no answer within 1.5 s; --open-timeout sets the wait), skipped"),
            std::string::npos)
      << run.err;
  EXPECT_LT(run.total, std::chrono::seconds(10));
  const auto zero = Chromatag({"detect", "--open-timeout", "0", silent.url()});
  EXPECT_EQ(zero.exit_code, 2) << zero.err;
}

INSTANTIATE_TEST_SUITE_P(Signals, CliStalledStreamTest,
                         ::testing::Values(std::vector<int>{SIGINT},
                                           std::vector<int>{SIGINT, SIGINT},
                                           std::vector<int>{SIGTERM}));

// Inputs say what they are: a missing camera device and a negative camera
// index are exit 2 like any missing input; a folder's subfolders are named,
// not silently passed over; a file that is not an image says which are;
// AprilTag's family names are accepted.
TEST(CliLiveTest, InputsSayWhatTheyAre) {
  const std::string dir = FreshDir("inputs");
  MakeClip(dir, "clip.avi", 3);
  fs::create_directories(dir + "/sub");
  std::ofstream(dir + "/sheet.pdf") << "%PDF-1.4\n";
  const auto device = Chromatag({"detect", "/dev/video97"});
  EXPECT_EQ(device.exit_code, 2);
  EXPECT_NE(device.err.find("no such file or folder: '/dev/video97'"), std::string::npos)
      << device.err;
  const auto url = Chromatag({"detect", "file://" + dir + "/missing.avi"});
  EXPECT_EQ(url.exit_code, 2);
  EXPECT_NE(url.err.find("no such file or folder: 'file://" + dir + "/missing.avi'"),
            std::string::npos)
      << url.err;
  // A camera index with no camera: tried, named, exit 1 (and under
  // AddressSanitizer no third-party leak reported, cmake/lsan.supp).
  const auto absent = Chromatag({"detect", "--camera-index", "99"});
  EXPECT_EQ(absent.exit_code, 1) << absent.err;
  EXPECT_NE(absent.err.find("cannot open camera or stream 'camera 99', skipped"), std::string::npos)
      << absent.err;
  // A FIFO named as a file URL would block the reader forever.
  ASSERT_EQ(mkfifo((dir + "/f.png").c_str(), 0600), 0);
  const auto fifo = Chromatag({"detect", "file://" + dir + "/f.png"});
  EXPECT_EQ(fifo.exit_code, 2);
  EXPECT_NE(fifo.err.find("is not a regular file"), std::string::npos) << fifo.err;
  const auto index = Chromatag({"detect", "--camera-index", "-1"});
  EXPECT_EQ(index.exit_code, 2);
  EXPECT_NE(index.err.find("a camera index is 0 or more"), std::string::npos) << index.err;
  // The FIFO inside the folder is named and skipped, as bad entries are.
  const auto folder = Chromatag({"detect", "--family", "tag16h5", dir});
  EXPECT_EQ(folder.exit_code, 1) << folder.err;
  EXPECT_NE(folder.err.find("'" + dir + "/sub' is a folder inside '" + dir + "', not read"),
            std::string::npos)
      << folder.err;
  EXPECT_NE(folder.err.find("'" + dir + "/f.png': a FIFO, skipped"), std::string::npos)
      << folder.err;
  const auto pdf = Chromatag({"detect", dir + "/sheet.pdf"});
  EXPECT_EQ(pdf.exit_code, 1);
  EXPECT_NE(pdf.err.find("a PDF or SVG sheet is checked by chromatag verify"), std::string::npos)
      << pdf.err;
}

TEST(CliLiveTest, BadLiveUsageIsExitTwo) {
  const auto show = testing::RunCommand(
      "/usr/bin/env", {"-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", CHROMATAG_CLI_PATH, "detect",
                       "--show", "--camera-index", "0"});
  EXPECT_EQ(show.exit_code, 2);
  EXPECT_NE(show.err.find("--show needs a display"), std::string::npos) << show.err;
  const auto missing = Chromatag({"detect", "--json", "/nonexistent/a.png", "/nonexistent/b.avi"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_TRUE(missing.out.empty()) << missing.out;
  EXPECT_EQ(CountLines(missing.err), 1) << missing.err;
  EXPECT_NE(missing.err.find("'/nonexistent/a.png' (and 1 more)"), std::string::npos)
      << missing.err;
}

}  // namespace
}  // namespace chromatag
