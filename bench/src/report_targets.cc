// The report's targets: recall against AprilTag 3 and against fixed bounds,
// per print, family and condition, then false detections and speed, each
// row with a verdict.
#include <cmath>
#include <map>

#include "report_util.h"

namespace chromatag::bench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Recalls that are equal but for rounding pass.
constexpr double kSlack = 1e-9;
constexpr double kLargeTagRecall = 0.995;  // Tags of kLargeTagPx and more.
constexpr double kLargeTagPx = 50.0;
constexpr double kMidTagPx = 30.0;
constexpr double kPointsBelowAprilTag = 0.01;  // Tags of kMidTagPx and more.
constexpr double kMaxTilt = 60.0;
constexpr double kTagFrameSpeedup = 20.0, kTagFreeSpeedup = 40.0;

using FramePredicate = std::function<bool(const FrameTruth&)>;

Verdict Judge(bool known, bool pass) {
  return !known ? Verdict::kNotApplicable : pass ? Verdict::kPass : Verdict::kFail;
}

TargetRow Row(const std::string& target, const std::string& wanted, const std::string& family,
              const std::string& chromatag, const std::string& apriltag, Verdict verdict) {
  TargetRow row;
  row.target = target;
  row.wanted = wanted;
  row.family = family;
  row.chromatag = chromatag;
  row.apriltag = apriltag;
  row.verdict = verdict;
  return row;
}

std::string RecallText(const Tally& t) {
  return t.tags > 0 ? Percent(t.hits, t.tags) + " % (" + Grouped(t.tags) + ")" : "– (0)";
}

// Tags of `family` of [lo, hi) px seen at up to kMaxTilt, on frames `frame` keeps.
TagFilter Keep(const std::string& family, double lo, double hi, const FramePredicate& frame) {
  return [=](const FrameTruth& f, const TagTruth& t) {
    return f.family == family && t.size_px >= lo && t.size_px < hi &&
           t.view_angle_deg <= kMaxTilt && frame(f);
  };
}

FramePredicate OfPrint(PrintKind print) {
  return [print](const FrameTruth& f) { return f.print == print; };
}

std::string PrintLabel(PrintKind print) { return "`" + std::string(PrintKindName(print)) + "`"; }

// `ours` at least AprilTag 3's recall on the same range, less `allowance`.
TargetRow AgainstAprilTag(const Context& c, const std::string& target, const std::string& wanted,
                          const std::string& family, const Tally& ours, const Tally& april,
                          double allowance) {
  const bool active = c.info.active[kAprilTag];
  const bool known = active && ours.tags > 0 && april.tags > 0;
  return Row(target, wanted, family, RecallText(ours), active ? RecallText(april) : "n/a",
             Judge(known, ours.Recall() >= april.Recall() - allowance - kSlack));
}

// ChromaTag's recall on tags of kLargeTagPx and more, at least kLargeTagRecall.
TargetRow LargeTags(const Context& c, const std::string& target, const std::string& family,
                    const FramePredicate& frame) {
  const auto tally = Count(c, Keep(family, kLargeTagPx, kInf, frame));
  return Row(
      target, "≥ " + Fixed(100 * kLargeTagRecall, 1) + " %", family, RecallText(tally[kChromaTag]),
      c.info.active[kAprilTag] ? RecallText(tally[kAprilTag]) : "n/a",
      Judge(tally[kChromaTag].tags > 0, tally[kChromaTag].Recall() >= kLargeTagRecall - kSlack));
}

// The conditions whose tags of kLargeTagPx and more are held to kLargeTagRecall.
std::vector<FrameCondition> LargeTagConditions() {
  std::vector<FrameCondition> conditions = CastConditions();
  conditions.push_back({"light ×0.3–0.5", [](const FrameTruth& f) { return f.exposure < 0.5; }});
  conditions.push_back({"JPEG quality 60–69", [](const FrameTruth& f) {
                          return f.jpeg_quality >= 60 && f.jpeg_quality < 70;
                        }});
  conditions.push_back(
      {"blur σ 1–1.5 px", [](const FrameTruth& f) { return f.blur_sigma_px >= 1.0; }});
  for (const BayerMode mode : {BayerMode::kBilinear, BayerMode::kEdgeAware}) {
    conditions.push_back({std::string("Bayer ") + BayerModeName(mode),
                          [mode](const FrameTruth& f) { return f.bayer == mode; }});
  }
  return conditions;
}

void RecallRows(const Context& c, const std::string& family, std::vector<TargetRow>* rows) {
  const std::string mid = "≥ " + Fixed(kMidTagPx, 0) + " px at ≤ " + Fixed(kMaxTilt, 0) + "°";
  const std::string large = "≥ " + Fixed(kLargeTagPx, 0) + " px at ≤ " + Fixed(kMaxTilt, 0) + "°";
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    const auto tally = Count(c, Keep(family, kMidTagPx, kInf, OfPrint(print)));
    rows->push_back(AgainstAprilTag(c, PrintLabel(print) + ": " + mid, "≥ AprilTag 3's − 1 point",
                                    family, tally[kChromaTag], tally[kAprilTag],
                                    kPointsBelowAprilTag));
  }
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    rows->push_back(LargeTags(c, PrintLabel(print) + ": " + large, family, OfPrint(print)));
  }
  for (const FrameCondition& condition : LargeTagConditions()) {
    rows->push_back(LargeTags(c, condition.name + ", all prints: " + large, family, condition.has));
  }
  const bool calibrated = AnyCalibrated(c);
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    const TagFilter keep = Keep(family, kMidTagPx, kInf, OfPrint(print));
    TargetRow row =
        AgainstAprilTag(c, PrintLabel(print) + ", calibrated: " + mid, "≥ AprilTag 3's", family,
                        CountCalibrated(c, keep), Count(c, keep)[kAprilTag], 0.0);
    if (!calibrated) {
      row.chromatag = "(not run)";
      row.verdict = Verdict::kNotApplicable;
    }
    rows->push_back(row);
  }
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    const auto tally = Count(c, Keep(family, 0.0, kMidTagPx, OfPrint(print)));
    rows->push_back(AgainstAprilTag(
        c,
        PrintLabel(print) + ": < " + Fixed(kMidTagPx, 0) + " px at ≤ " + Fixed(kMaxTilt, 0) + "°",
        "≥ AprilTag 3's", family, tally[kChromaTag], tally[kAprilTag], 0.0));
  }
}

// Detections that are not the first on the true tag, wrong IDs and duplicates.
struct Errors {
  int false_detections = 0, wrong_ids = 0, duplicates = 0;
  void Add(const FrameScore& s) {
    false_detections += s.false_positives;
    wrong_ids += s.wrong_ids;
    duplicates += s.duplicates;
  }
};

void ErrorRows(const Context& c, std::vector<TargetRow>* rows) {
  std::array<Errors, kNumDetectors> errors;
  Errors calibrated;
  for (const auto& r : c.records) {
    for (int d = 0; d < kNumDetectors; ++d) {
      if (r.detectors[d].ran) errors[d].Add(r.detectors[d].score);
    }
    if (r.calibrated.ran) calibrated.Add(r.calibrated.score);
  }
  const bool april = c.info.active[kAprilTag], cal = AnyCalibrated(c);
  auto add = [&](const std::string& what, int Errors::*field) {
    const int ours = errors[kChromaTag].*field, calibrated_ones = calibrated.*field;
    TargetRow row =
        Row(what, "0", "", Grouped(ours), april ? Grouped(errors[kAprilTag].*field) : "n/a",
            Judge(true, ours == 0 && calibrated_ones == 0));
    row.calibrated = cal ? Grouped(calibrated_ones) : "(not run)";
    rows->push_back(row);
  };
  add("false detections (any but the first on the true tag), all frames",
      &Errors::false_detections);
  add("of which wrong IDs (a wrong family or ID on the true tag)", &Errors::wrong_ids);
  add("of which duplicates (the true tag again, right ID)", &Errors::duplicates);
}

// Mean times (the paper's frames per second) in the timed loop, where the
// detectors take turns on each frame.
void SpeedRows(const Context& c, std::vector<TargetRow>* rows) {
  std::array<std::array<std::vector<double>, kNumDetectors>, 2> times;  // Tags, tag-free.
  std::array<std::vector<double>, 2> alone;
  for (const auto& r : c.records) {
    const int g = r.truth.has_tags ? 0 : 1;
    for (int d = 0; d < kNumDetectors; ++d) {
      if (r.detectors[d].ran) times[g][d].push_back(r.detectors[d].time_us);
    }
    if (!std::isnan(r.chromatag_alone_us)) alone[g].push_back(r.chromatag_alone_us);
  }
  const bool april = c.info.active[kAprilTag];
  const char* names[2] = {"frames with tags", "tag-free frames"};
  const double floors[2] = {kTagFrameSpeedup, kTagFreeSpeedup};
  for (int g = 0; g < 2; ++g) {
    const double ours = Mean(times[g][kChromaTag]), theirs = Mean(times[g][kAprilTag]);
    const double ratio = theirs / ours;
    TargetRow row =
        Row(std::string("speed, ") + names[g] + ": AprilTag 3's mean time ÷ ChromaTag's",
            "≥ " + Fixed(floors[g], 0) + "×", "",
            (april ? Fixed(ratio, 1) + "× (" : "(") + Fixed(ours, 1) + " µs)",
            april ? Fixed(theirs, 1) + " µs" : "n/a",
            Judge(april && !times[g][kChromaTag].empty() && !times[g][kAprilTag].empty(),
                  ratio >= floors[g]));
    row.calibrated = "(untimed)";
    rows->push_back(row);
    if (!alone[g].empty()) {
      const double solo = Mean(alone[g]);
      rows->push_back(Row(std::string("(for comparison) ") + names[g] + ", ChromaTag alone", "", "",
                          Fixed(theirs / solo, 1) + "× (" + Fixed(solo, 1) + " µs)", "",
                          Verdict::kNotApplicable));
    }
  }
}

const char* VerdictText(Verdict v) {
  return v == Verdict::kPass ? "pass" : v == Verdict::kFail ? "**fail**" : "n/a";
}

// Rows with a family, one line per target and the families side by side.
std::string RecallTable(const Context& c, const std::vector<TargetRow>& rows) {
  const std::vector<std::string> families = DatasetFamilies(c.info.dataset.kind);
  std::vector<std::string> order;
  std::map<std::string, std::vector<std::string>> lines;
  for (const TargetRow& row : rows) {
    if (row.family.empty()) continue;
    auto [it, fresh] = lines.try_emplace(row.target);
    if (fresh) order.push_back(row.target), it->second = {row.target, row.wanted};
    it->second.insert(it->second.end(), {row.chromatag, row.apriltag, VerdictText(row.verdict)});
  }
  std::vector<std::string> header = {"target", "wanted"};
  for (const std::string& family : families) {
    header.insert(header.end(),
                  {family + ": " + c.info.names[kChromaTag], c.info.names[kAprilTag], "verdict"});
  }
  Table table;
  for (const std::string& target : order) table.push_back(lines[target]);
  return Markdown(header, table);
}

// Rows over the whole set; the calibrated configs' column on the camera set.
std::string SetTable(const Context& c, const std::vector<TargetRow>& rows) {
  const bool camera = c.info.dataset.kind == DatasetKind::kCamera;
  Table table;
  for (const TargetRow& row : rows) {
    if (!row.family.empty()) continue;
    table.push_back({row.target, row.wanted, row.chromatag});
    if (camera) table.back().push_back(row.calibrated);
    table.back().push_back(row.apriltag);
    table.back().push_back(row.wanted.empty() ? "–" : VerdictText(row.verdict));
  }
  std::vector<std::string> header = {"target", "wanted", c.info.names[kChromaTag]};
  if (camera) header.push_back("calibrated configs");
  header.insert(header.end(), {c.info.names[kAprilTag], "verdict"});
  return Markdown(header, table);
}

}  // namespace

std::vector<TargetRow> CheckTargets(const Context& c) {
  std::vector<TargetRow> rows;
  if (c.info.dataset.kind == DatasetKind::kCamera) {
    for (const std::string& family : DatasetFamilies(c.info.dataset.kind)) {
      RecallRows(c, family, &rows);
    }
  }
  ErrorRows(c, &rows);
  SpeedRows(c, &rows);
  return rows;
}

std::string TargetsSection(const Context& c) {
  const std::vector<TargetRow> rows = CheckTargets(c);
  std::array<int, 3> verdicts{};
  for (const TargetRow& row : rows) {
    if (!row.wanted.empty()) ++verdicts[static_cast<int>(row.verdict)];
  }
  const bool camera = c.info.dataset.kind == DatasetKind::kCamera;
  std::ostringstream out;
  out << "### Targets\n\n"
      << "Of " << Grouped(verdicts[0] + verdicts[1] + verdicts[2]) << " checks, "
      << Grouped(verdicts[static_cast<int>(Verdict::kPass)]) << " pass, "
      << Grouped(verdicts[static_cast<int>(Verdict::kFail)]) << " fail, "
      << Grouped(verdicts[static_cast<int>(Verdict::kNotApplicable)])
      << " n/a (AprilTag 3 or the calibrated configs not run, or no tag in the range). ";
  if (camera) {
    out << "Recall of each detector against its own tag, per family, in % (tags counted in "
           "brackets); tilt is the viewing angle. \"All prints\" rows hold the tags of every "
           "print on frames with that condition; a cast is the one at the card's centre "
           "(\"Recall per cast and light level\"). \"Calibrated\": ChromaTag with the config "
           "`chromatag calibrate` derives for the print.\n\n"
        << RecallTable(c, rows) << "\n";
  }
  out << "False detections count every detection but the first on the true tag (\"False "
         "detections\")"
      << (camera ? "; the calibrated configs run on their print's frames and on every tag-free "
                   "frame"
                 : "")
      << ". Speed is the ratio of mean times per frame in the timed loop of this "
         "run, the detectors taking turns on each frame (Table 1's frames per second); the "
         "microseconds are a guide to this machine only.\n\n"
      << SetTable(c, rows);
  return out.str();
}

}  // namespace chromatag::bench
