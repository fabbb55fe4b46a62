// One progress line on stderr, shared by the commands: "detect [####   ]
// 120/400 frames, 850/s". Drawn only when stderr is a terminal, at most ten
// times a second; cleared when done, so that what follows starts on a clean
// line. Without a known total it shows the count and the rate.
#ifndef CHROMATAG_CLI_PROGRESS_H_
#define CHROMATAG_CLI_PROGRESS_H_

#include <chrono>
#include <cstddef>
#include <string>

namespace chromatag::cli {

class Progress {
 public:
  // `unit` names what is counted ("frames", "tags"); total 0 means unknown.
  Progress(std::string label, std::string unit, size_t total = 0);
  ~Progress();

  void set_total(size_t total) { total_ = total; }
  void Update(size_t done);
  // Clears the line (when one was drawn).
  void Finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  std::string unit_;
  size_t total_;
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point last_draw_;
};

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_PROGRESS_H_
