// What the report's files share: the run's context and small formatting
// helpers. Private to the bench library.
#ifndef CHROMATAG_BENCH_SRC_REPORT_UTIL_H_
#define CHROMATAG_BENCH_SRC_REPORT_UTIL_H_

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "chromatag/bench/comparison.h"

namespace chromatag::bench {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

inline std::string Fixed(double value, int digits) {
  if (std::isnan(value)) return "–";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

// Thousands separated by a thin space: 12 345.
inline std::string Grouped(double value) {
  if (std::isnan(value)) return "–";
  std::string digits = std::to_string(static_cast<long long>(std::llround(value)));
  const bool negative = !digits.empty() && digits[0] == '-';
  if (negative) digits.erase(0, 1);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += "\u2009";
    out += digits[i];
  }
  return negative ? "-" + out : out;
}

inline std::string Percent(double numerator, double denominator, int digits = 1) {
  return denominator > 0 ? Fixed(100.0 * numerator / denominator, digits) : "–";
}

using Table = std::vector<std::vector<std::string>>;

inline std::string Markdown(const std::vector<std::string>& header, const Table& rows) {
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (const auto& cell : cells) out << " " << cell << " |";
    out << "\n";
  };
  line(header);
  out << "|";
  for (size_t i = 0; i < header.size(); ++i) out << (i == 0 ? "---|" : "---:|");
  out << "\n";
  for (const auto& row : rows) line(row);
  return out.str();
}

inline double Mean(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0;
  for (double v : values) sum += v;
  return sum / values.size();
}

inline const TagTruth& OwnTruth(const FrameRecord& record, int detector) {
  return detector == kChromaTag ? record.truth.chromatag : record.truth.apriltag;
}

struct Context {
  const std::vector<FrameRecord>& records;
  const ReportInfo& info;
  std::string out_dir;
  std::string* error;
  int tagged = 0, tag_free = 0;
};

// Which tags count: the frame (for its conditions) and the detector's own tag.
using TagFilter = std::function<bool(const FrameTruth&, const TagTruth&)>;

struct Tally {
  int tags = 0, hits = 0;
  double Recall() const { return tags > 0 ? static_cast<double>(hits) / tags : kNaN; }
};

// Each active detector against its own tag, over the tags `filter` keeps.
std::array<Tally, kNumDetectors> Count(const Context& c, const TagFilter& filter);
// ChromaTag with the calibrated config of each frame's print, on the tags
// `filter` keeps (CalibratedDetectors); no tags when it did not run.
Tally CountCalibrated(const Context& c, const TagFilter& filter);
bool AnyCalibrated(const Context& c);

// A condition of the frame, named for a row of a table.
struct FrameCondition {
  std::string name;
  std::function<bool(const FrameTruth&)> has;
};
// The camera set's casts at the card: each CastKind, strong casts
// (IsStrongCast), mixed light.
std::vector<FrameCondition> CastConditions();

// Sections of the report that break recall down (report_breakdown.cc).
std::string FamilyRecallSection(const Context& c);
std::string ConditionRecallSection(const Context& c);
std::string PrintRecallSection(const Context& c);  // Camera set only; empty otherwise.
std::string CastRecallSection(const Context& c);   // Camera set only; empty otherwise.
std::string PoseSection(const Context& c);         // Camera set only; empty otherwise.
// How well detector `d`'s pose covariance (ChromaTag's own, AprilTag 3's
// assumed) predicts its errors, over its own tags that `keep` keeps (per
// axis in ROS order, and the 95 % ellipsoid).
CovarianceTally CalibrationOfPoses(const Context& c, int d,
                                   const std::function<bool(const TagTruth&)>& keep);
std::string PoseUncertaintySection(const Context& c);  // Camera set only; empty otherwise.
std::string MissTable(const Context& c);               // Table 4(b), from the miss analysis.

enum class Verdict { kNotApplicable = 0, kPass = 1, kFail = 2 };

// One row of the Targets section: what ChromaTag (or its calibrated
// configs) measured against what is wanted, for one family (recall) or the
// whole set (false detections, speed). Rows with no `wanted` are shown for
// comparison and judge nothing.
struct TargetRow {
  std::string target;
  std::string wanted;
  std::string family;      // Empty for a row over the whole set.
  std::string chromatag;   // What ChromaTag (or its calibrated configs) measured.
  std::string calibrated;  // Rows over the whole set: the calibrated configs' ("" if not run).
  std::string apriltag;    // AprilTag 3's on the same range, or "n/a".
  Verdict verdict = Verdict::kNotApplicable;
};

// The targets (report_targets.cc): on the camera set, recall per family
// against AprilTag 3 and against 99.5 %, per print and per condition; on
// every set, false detections, wrong IDs and duplicates, and speed against
// AprilTag 3 measured in the same run.
std::vector<TargetRow> CheckTargets(const Context& c);
std::string TargetsSection(const Context& c);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_SRC_REPORT_UTIL_H_
