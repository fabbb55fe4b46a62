#include "library_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <thread>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CHROMATAG_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define CHROMATAG_SANITIZED 1
#endif
#endif

#ifdef CHROMATAG_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace chromatag::cli {
namespace {

std::FILE* g_tool_err = nullptr;
int g_tool_fd = -1;
int g_pipe_fd = -1;  // The read end, drained by Drain (and by a crash).

// The last kKept bytes the libraries wrote, as a ring: read by the fatal
// signal handler with plain loads (a line torn by a concurrent write is
// acceptable in a crash report).
constexpr size_t kKept = 4096;
char g_kept[kKept];
std::atomic<size_t> g_written{0};

void WriteAll(int fd, const char* data, size_t n) {
  while (n > 0) {
    const ssize_t done = write(fd, data, n);
    if (done < 0 && errno == EINTR) continue;
    if (done <= 0) return;
    data += done;
    n -= static_cast<size_t>(done);
  }
}

void Keep(const char* data, size_t n) {
  size_t written = g_written.load(std::memory_order_relaxed);
  for (size_t i = 0; i < n; ++i) g_kept[(written + i) % kKept] = data[i];
  g_written.store(written + n, std::memory_order_relaxed);
}

void OnFatalSignal(int signal) {
  // Only async-signal-safe calls: fcntl, read, write, signal, raise. What
  // was written just before the crash ("terminate called after ...") may
  // still be in the pipe: read it first.
  const int pipe_fd = g_pipe_fd;
  if (pipe_fd >= 0 && fcntl(pipe_fd, F_SETFL, fcntl(pipe_fd, F_GETFL) | O_NONBLOCK) == 0) {
    char buffer[512];
    for (ssize_t n; (n = read(pipe_fd, buffer, sizeof buffer)) > 0;)
      Keep(buffer, static_cast<size_t>(n));
  }
  const size_t written = g_written.load(std::memory_order_relaxed);
  if (written > 0 && g_tool_fd >= 0) {
    static const char kHead[] = "chromatag: what libraries printed before the crash:\n";
    WriteAll(g_tool_fd, kHead, sizeof(kHead) - 1);
    if (written >= kKept) {  // The ring is full: from the oldest byte on.
      const size_t start = written % kKept;
      WriteAll(g_tool_fd, g_kept + start, kKept - start);
      WriteAll(g_tool_fd, g_kept, start);
    } else {
      WriteAll(g_tool_fd, g_kept, written);
    }
    WriteAll(g_tool_fd, "\n", 1);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void Drain(int fd) {
  char buffer[1024];
  for (;;) {
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    Keep(buffer, static_cast<size_t>(n));
  }
}

}  // namespace

void CaptureLibraryOutput() {
  const char* through = std::getenv("CHROMATAG_LIBRARY_OUTPUT");
  if (through != nullptr && std::strcmp(through, "1") == 0) return;
  const int tool_fd = fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3);
  if (tool_fd < 0) return;
  int pipe_fds[2];
  if (pipe2(pipe_fds, O_CLOEXEC) != 0) {
    close(tool_fd);
    return;
  }
  std::FILE* tool_err = fdopen(tool_fd, "w");
  if (tool_err == nullptr || dup2(pipe_fds[1], STDERR_FILENO) < 0) {
    if (tool_err)
      std::fclose(tool_err);
    else
      close(tool_fd);
    close(pipe_fds[0]);
    close(pipe_fds[1]);
    return;
  }
  close(pipe_fds[1]);
  std::setvbuf(tool_err, nullptr, _IONBF, 0);  // As stderr: nothing held back.
  g_tool_err = tool_err;
  g_tool_fd = tool_fd;
  g_pipe_fd = pipe_fds[0];
  std::thread(Drain, pipe_fds[0]).detach();
#ifdef CHROMATAG_SANITIZED
  // The sanitizer's reports go where the tool's messages go, and it keeps
  // its own handlers but for abort (which it leaves alone by default).
  __sanitizer_set_report_fd(reinterpret_cast<void*>(static_cast<intptr_t>(tool_fd)));
  std::signal(SIGABRT, OnFatalSignal);
#else
  for (int signal : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL}) std::signal(signal, OnFatalSignal);
#endif
}

std::FILE* ToolErr() { return g_tool_err != nullptr ? g_tool_err : stderr; }

}  // namespace chromatag::cli
