#include "progress.h"

#include <unistd.h>

#include <cstdio>

#include "library_output.h"

namespace chromatag::cli {

Progress::Progress(std::string label, std::string unit, size_t total)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(isatty(fileno(ToolErr())) == 1),
      start_(Clock::now()),
      last_draw_(start_ - std::chrono::seconds(1)) {}

Progress::~Progress() { Finish(); }

void Progress::Update(size_t done) {
  if (!enabled_) return;
  const Clock::time_point now = Clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && done != total_) return;
  last_draw_ = now;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  const double rate = seconds > 0 ? static_cast<double>(done) / seconds : 0.0;
  if (total_ > 0) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * std::min(done, total_) / total_);
    std::fprintf(ToolErr(), "\r\033[K%s [%s%s] %zu/%zu %s, %.0f/s", label_.c_str(),
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, ' ').c_str(), done,
                 total_, unit_.c_str(), rate);
  } else {
    std::fprintf(ToolErr(), "\r\033[K%s %zu %s, %.0f/s", label_.c_str(), done, unit_.c_str(), rate);
  }
  std::fflush(ToolErr());
  drawn_ = true;
}

void Progress::Finish() {
  if (!drawn_) return;
  std::fprintf(ToolErr(), "\r\033[K");
  std::fflush(ToolErr());
  drawn_ = false;
}

}  // namespace chromatag::cli
