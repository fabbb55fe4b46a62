// The camera calibration comparison's report: report.md (what was run, the
// results against the limits and against ChArUco, every trial) and
// results.json (every number). Private to calib_comparison.
#ifndef CHROMATAG_BENCH_SRC_CALIB_REPORT_H_
#define CHROMATAG_BENCH_SRC_CALIB_REPORT_H_

#include <string>
#include <vector>

#include "calib_trial.h"

namespace chromatag::bench {

struct CalibrationRunInfo {
  std::string command;  // As typed.
  std::string label;    // What was measured (a commit).
  std::string cpu;
  std::string build;  // Build type and code generation flags.
  std::string load;   // Load averages before and after.
  TrialOptions options;
  double render_s = 0;  // Every trial's rendering, wall time.
  double total_s = 0;
  std::string chromatag_board, charuco_board;  // PrintedBoard::description.
};

// Writes out_dir/report.md and out_dir/results.json; false and *error when
// a file cannot be written. *markdown gets the report.
bool WriteCalibrationReport(const std::vector<TrialResult>& trials, const CalibrationRunInfo& info,
                            const std::string& out_dir, std::string* markdown, std::string* error);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_SRC_CALIB_REPORT_H_
