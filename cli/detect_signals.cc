#include "detect_signals.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>

#include "library_output.h"

namespace chromatag::cli {

std::atomic<bool> g_stop{false};
std::atomic<bool> g_stop_now{false};
std::atomic<int> g_signal{0};
std::atomic<int> g_writing{0};
std::atomic<bool> g_end_after_writes{false};
static_assert(std::atomic<int>::is_always_lock_free && std::atomic<bool>::is_always_lock_free,
              "used in a signal handler");

namespace {

constexpr int kEndingSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};

void OnSignal(int signal) {
  g_signal = signal;
  if (!g_stop.exchange(true)) return;
  if (!g_stop_now.exchange(true)) return;
  // A third signal ends the process at once, whatever it is stuck in, but
  // not around an overlay being written (it would leave its temporaries):
  // then the write ends it. A fourth does not wait even for that.
  if (g_writing == 0 || g_end_after_writes.exchange(true)) EndBy(signal);
}

}  // namespace

void CatchEndingSignals() {
  g_stop = false;
  g_stop_now = false;
  g_end_after_writes = false;
  g_signal = 0;
  for (int s : kEndingSignals) std::signal(s, OnSignal);
}

void ReleaseEndingSignals() {
  for (int s : kEndingSignals) std::signal(s, SIG_DFL);
}

void EndBy(int signal) {
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

void DieBy(int signal) {
  std::fflush(stdout);
  std::fflush(ToolErr());
  std::signal(signal, SIG_DFL);
  std::raise(signal);
  std::_Exit(128 + signal);
}

}  // namespace chromatag::cli
