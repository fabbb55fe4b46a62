// The report's breakdowns: recall per family by size and tilt, per print,
// per condition and per cast and light level, pose, and Table 4(b) from the
// miss analysis.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "chromatag/bench/cast.h"
#include "report_util.h"

namespace chromatag::bench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Range {
  std::string name;
  double lo, hi;  // [lo, hi)
  bool Contains(double v) const { return v >= lo && v < hi; }
};

const Range kSizeGroups[] = {{"< 30 px", 0, 30},       {"30–50 px", 30, 50},
                             {"50–70 px", 50, 70},     {"70–100 px", 70, 100},
                             {"100–150 px", 100, 150}, {"≥ 150 px", 150, kInf}};
const Range kTiltGroups[] = {
    {"0–30°", 0, 30}, {"30–45°", 30, 45}, {"45–60°", 45, 60}, {"60–75°", 60, kInf}};

std::string RecallCell(const Context& c, const std::array<Tally, kNumDetectors>& tally, int d) {
  return c.info.active[d] ? Percent(tally[d].hits, tally[d].tags) : "n/a";
}

std::vector<std::string> Families(const Context& c) {
  std::set<std::string> names;
  for (const auto& r : c.records) {
    if (r.truth.has_tags) names.insert(r.truth.family);
  }
  return {names.begin(), names.end()};
}

bool Squarish(const TagTruth& t) { return t.size_px >= 30 && t.view_angle_deg <= 60; }
bool UpTo60(const TagTruth& t) { return t.view_angle_deg <= 60; }

}  // namespace

std::array<Tally, kNumDetectors> Count(const Context& c, const TagFilter& filter) {
  std::array<Tally, kNumDetectors> tally;
  for (const auto& r : c.records) {
    if (!r.truth.has_tags) continue;
    for (int d = 0; d < kNumDetectors; ++d) {
      if (!c.info.active[d] || !filter(r.truth, OwnTruth(r, d))) continue;
      ++tally[d].tags;
      tally[d].hits += r.detectors[d].score.found ? 1 : 0;
    }
  }
  return tally;
}

Tally CountCalibrated(const Context& c, const TagFilter& filter) {
  Tally tally;
  for (const auto& r : c.records) {
    if (!r.truth.has_tags || !r.calibrated.ran || !filter(r.truth, r.truth.chromatag)) continue;
    ++tally.tags;
    tally.hits += r.calibrated.score.found ? 1 : 0;
  }
  return tally;
}

bool AnyCalibrated(const Context& c) {
  return std::any_of(c.records.begin(), c.records.end(),
                     [](const FrameRecord& r) { return r.calibrated.ran; });
}

std::vector<FrameCondition> CastConditions() {
  std::vector<FrameCondition> conditions;
  for (int k = 0; k < kNumCastKinds; ++k) {
    const std::string name = CastKindName(static_cast<CastKind>(k));
    conditions.push_back({"cast " + name, [name](const FrameTruth& f) { return f.cast == name; }});
  }
  const std::string strong =
      "strong cast (a gain ≤ " + Fixed(kStrongLow, 1) + " or ≥ " + Fixed(kStrongHigh, 1) + ")";
  conditions.push_back({strong, [](const FrameTruth& f) {
                          return IsStrongCast({f.red_gain, f.blue_gain});
                        }});
  conditions.push_back({"mixed light", [](const FrameTruth& f) { return f.mixed_light; }});
  return conditions;
}

std::string FamilyRecallSection(const Context& c) {
  std::ostringstream out;
  out << "### Recall per family by size and tilt\n\n"
      << "Each detector against its own tag (sizes and tilts of the ChromaTag and its AprilTag "
         "twin differ a little, so the tag counts, the ChromaTags', are approximate for the "
         "others). Size: square root of the black square's area; tilt: viewing angle.\n\n";
  for (const std::string& family : Families(c)) {
    Table rows;
    auto add = [&](const std::string& label, const TagFilter& filter) {
      const auto tally = Count(c, [&](const FrameTruth& f, const TagTruth& t) {
        return f.family == family && filter(f, t);
      });
      if (tally[kChromaTag].tags == 0) return;
      rows.push_back({label, Grouped(tally[kChromaTag].tags), RecallCell(c, tally, kChromaTag),
                      RecallCell(c, tally, kAprilTag), RecallCell(c, tally, kAruco)});
    };
    for (const Range& size : kSizeGroups) {
      add("size " + size.name,
          [&](const FrameTruth&, const TagTruth& t) { return size.Contains(t.size_px); });
    }
    for (const Range& tilt : kTiltGroups) {
      add("tilt " + tilt.name,
          [&](const FrameTruth&, const TagTruth& t) { return tilt.Contains(t.view_angle_deg); });
    }
    add("all", [](const FrameTruth&, const TagTruth&) { return true; });
    out << "**" << family << "**\n\n"
        << Markdown({"range", "tags", c.info.names[kChromaTag] + " %",
                     c.info.names[kAprilTag] + " %", c.info.names[kAruco] + " %"},
                    rows)
        << "\n";
  }
  return out.str();
}

std::string PrintRecallSection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera) return "";
  const bool calibrated = AnyCalibrated(c);
  std::ostringstream out;
  out << "### Recall per print by size and tilt\n\n"
      << "The camera set's tags are printed four ways: the default palette as its file says "
         "(`default`) and through a CMYK SWOP press (`default-press`: Ghostscript's "
         "default_cmyk.icc, LittleCMS), the iccv17 palette (the shades the paper's authors "
         "measured on their prints) as its file says (`iccv17`) and faded further (`iccv17-faded`: "
         "a* and b* × "
      << Fixed(kFadedChroma, 1)
      << "). Sizes up to 60° of tilt, tilts from 30 px. Each detector against its own tag; "
         "\"calibrated\" is ChromaTag with the detector config `chromatag calibrate` derives from "
         "photos of that print's calibration sheet (calib-sheet in the print's palette, printed "
         "the same way, photographed under a tungsten lamp and daylight)"
      << (calibrated ? "" : " (not run)") << ".\n\n";
  if (!c.info.calibrated.empty()) {
    Table configs;
    for (const auto& [print, o] : c.info.calibrated) {
      configs.push_back({print, Fixed(o.adiff_thresh, 1), Fixed(o.border_thresh, 1),
                         Fixed(o.min_decision_margin, 1), Fixed(o.max_green_a, 1),
                         o.two_step_rises ? "on" : "off"});
    }
    out << "The calibrated configs (the defaults: " << Fixed(DetectorOptions{}.adiff_thresh, 1)
        << ", " << Fixed(DetectorOptions{}.border_thresh, 1) << ", "
        << Fixed(DetectorOptions{}.min_decision_margin, 1) << ", "
        << Fixed(DetectorOptions{}.max_green_a, 1) << ", off):\n\n"
        << Markdown({"print", "ADiffThresh", "BorderThresh", "min decision margin", "max green a*",
                     "two-step rises"},
                    configs)
        << "\n";
  }
  for (int k = 0; k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    Table rows;
    auto add = [&](const std::string& label, const TagFilter& filter) {
      std::vector<std::string> row = {label};
      for (const char* family : {"16h5", "36h11"}) {
        const TagFilter keep = [&](const FrameTruth& f, const TagTruth& t) {
          return f.print == print && f.family == family && filter(f, t);
        };
        const auto tally = Count(c, keep);
        const Tally cal = CountCalibrated(c, keep);
        row.insert(row.end(), {Grouped(tally[kChromaTag].tags), RecallCell(c, tally, kChromaTag),
                               calibrated ? Percent(cal.hits, cal.tags) : "n/a",
                               RecallCell(c, tally, kAprilTag), RecallCell(c, tally, kAruco)});
      }
      rows.push_back(row);
    };
    for (const Range& size : kSizeGroups) {
      add("size " + size.name, [&](const FrameTruth&, const TagTruth& t) {
        return size.Contains(t.size_px) && UpTo60(t);
      });
    }
    for (const Range& tilt : kTiltGroups) {
      add("tilt " + tilt.name, [&](const FrameTruth&, const TagTruth& t) {
        return tilt.Contains(t.view_angle_deg) && t.size_px >= 30;
      });
    }
    add("≥ 30 px, ≤ 60°", [](const FrameTruth&, const TagTruth& t) { return Squarish(t); });
    add("all", [](const FrameTruth&, const TagTruth&) { return true; });
    const std::string& ct = c.info.names[kChromaTag];
    const std::string& at = c.info.names[kAprilTag];
    const std::string& ar = c.info.names[kAruco];
    out << "**" << PrintKindName(print) << "**\n\n"
        << Markdown({"range", "16h5 tags", ct + " %", "calibrated %", at + " %", ar + " %",
                     "36h11 tags", ct + " %", "calibrated %", at + " %", ar + " %"},
                    rows)
        << "\n";
  }
  return out.str();
}

namespace {

// Light on the card (FrameTruth::exposure).
const std::vector<Range> kLightBins = {{"×0.3–0.5", 0, 0.5},
                                       {"×0.5–0.75", 0.5, 0.75},
                                       {"×0.75–1", 0.75, 1},
                                       {"×1–1.25", 1, 1.25},
                                       {"×1.25–1.5", 1.25, kInf}};
const std::vector<Range> kGainBins = {
    {"0.6–0.8", 0, 0.8}, {"0.8–1.2", 0.8, 1.2}, {"1.2–1.5", 1.2, kInf}};

// A row per bin of `field`.
void AddRanges(const std::string& what, const std::vector<Range>& bins, double FrameTruth::*field,
               std::vector<FrameCondition>* out) {
  for (const Range& bin : bins) {
    out->push_back({what + " " + bin.name,
                    [bin, field](const FrameTruth& f) { return bin.Contains(f.*field); }});
  }
}

// The rows of Recall per condition. The camera set's casts and light levels
// have their own section (CastRecallSection).
std::vector<FrameCondition> RecallConditions(const Context& c) {
  const bool camera = c.info.dataset.kind == DatasetKind::kCamera;
  std::vector<FrameCondition> out;
  for (const std::string family : {"16h5", "36h11"}) {
    out.push_back(
        {"family " + family, [family](const FrameTruth& f) { return f.family == family; }});
  }
  if (!camera) {
    for (const std::string cast : {"neutral", "tungsten"}) {
      out.push_back({"cast " + cast, [cast](const FrameTruth& f) { return f.cast == cast; }});
    }
    AddRanges("exposure", kLightBins, &FrameTruth::exposure, &out);
  }
  AddRanges("light gradient", {{"1–1.2×", 0, 1.2}, {"1.2–1.4×", 1.2, 1.4}, {"1.4–1.6×", 1.4, 9}},
            &FrameTruth::gradient, &out);
  AddRanges("tone gamma",
            {{"0.75–0.9", 0, 0.9},
             {"0.9–1.05", 0.9, 1.05},
             {"1.05–1.2", 1.05, 1.2},
             {"1.2–1.35", 1.2, 9}},
            &FrameTruth::tone_gamma, &out);
  AddRanges("blur σ", {{"0–0.5 px", 0, 0.5}, {"0.5–1 px", 0.5, 1}, {"1–1.5 px", 1, 9}},
            &FrameTruth::blur_sigma_px, &out);
  out.push_back({"motion blur none", [](const FrameTruth& f) { return f.motion_blur_px == 0; }});
  out.push_back({"motion blur 1–5 px", [](const FrameTruth& f) { return f.motion_blur_px > 0; }});
  AddRanges("shot noise SNR", {{"30–45", 1, 45}, {"45–60", 45, 60}, {"60–80", 60, 1e9}},
            &FrameTruth::shot_snr, &out);
  AddRanges("read noise σ", {{"0.002–0.006", 1e-9, 0.006}, {"0.006–0.01", 0.006, 1}},
            &FrameTruth::read_noise, &out);
  for (int mode = 0; mode < kNumBayerModes; ++mode) {
    const BayerMode bayer = static_cast<BayerMode>(mode);
    out.push_back({std::string("Bayer ") + BayerModeName(bayer),
                   [bayer](const FrameTruth& f) { return f.bayer == bayer; }});
  }
  out.push_back({"JPEG none", [](const FrameTruth& f) { return f.jpeg_quality == 0; }});
  out.push_back({"JPEG any", [](const FrameTruth& f) { return f.jpeg_quality > 0; }});
  for (const Range& q : std::vector<Range>{
           {"60–69", 60, 70}, {"70–79", 70, 80}, {"80–89", 80, 90}, {"90–95", 90, 101}}) {
    out.push_back({"JPEG quality " + q.name, [q](const FrameTruth& f) {
                     return f.jpeg_quality > 0 && q.Contains(f.jpeg_quality);
                   }});
  }
  for (int quiet : {1, 2}) {
    out.push_back({"quiet zone " + std::to_string(quiet) + (quiet == 1 ? " cell" : " cells"),
                   [quiet](const FrameTruth& f) { return f.quiet_zone_cells == quiet; }});
  }
  for (int k = 0; camera && k < kNumPrintKinds; ++k) {
    const PrintKind print = static_cast<PrintKind>(k);
    out.push_back({std::string("print ") + PrintKindName(print),
                   [print](const FrameTruth& f) { return f.print == print; }});
  }
  return out;
}

bool Large(const TagTruth& t) { return t.size_px >= 50 && t.view_angle_deg <= 60; }

}  // namespace

std::string ConditionRecallSection(const Context& c) {
  Table rows;
  for (const FrameCondition& condition : RecallConditions(c)) {
    const auto& has = condition.has;
    const auto all = Count(c, [&](const FrameTruth& f, const TagTruth&) { return has(f); });
    if (all[kChromaTag].tags == 0) continue;
    const auto squarish =
        Count(c, [&](const FrameTruth& f, const TagTruth& t) { return has(f) && Squarish(t); });
    const auto large =
        Count(c, [&](const FrameTruth& f, const TagTruth& t) { return has(f) && Large(t); });
    rows.push_back({condition.name, Grouped(all[kChromaTag].tags), RecallCell(c, all, kChromaTag),
                    RecallCell(c, all, kAprilTag), RecallCell(c, all, kAruco),
                    RecallCell(c, squarish, kChromaTag), RecallCell(c, squarish, kAprilTag),
                    RecallCell(c, large, kChromaTag), RecallCell(c, large, kAprilTag)});
  }
  const std::string& ct = c.info.names[kChromaTag];
  const std::string& at = c.info.names[kAprilTag];
  const bool camera = c.info.dataset.kind == DatasetKind::kCamera;
  return "### Recall per condition\n\n"
         "Every tag of the frames with each condition, both families" +
         std::string(camera ? " (casts and light levels: \"Recall per cast and light level\")"
                            : "") +
         ". Conditions are drawn "
         "independently of each other and of the camera path, so rows of one condition compare "
         "fairly; family and quiet zone are the exception: they change the card's size in "
         "black-square units, and the camera backs off further to fit a larger card, so their "
         "largest tags are a little smaller. The last four columns keep only tags of at least "
         "30 px, and of at least 50 px, seen at 60° or less, where the detectors are meant to "
         "work.\n\n" +
         Markdown({"condition", "tags", ct + " %", at + " %", c.info.names[kAruco] + " %",
                   ct + " % (≥ 30 px, ≤ 60°)", at + " % (≥ 30 px, ≤ 60°)",
                   ct + " % (≥ 50 px, ≤ 60°)", at + " % (≥ 50 px, ≤ 60°)"},
                  rows);
}

namespace {

// The rows of Recall per cast and light level.
std::vector<FrameCondition> CastAndLightConditions() {
  std::vector<FrameCondition> out = CastConditions();
  out.push_back({"one light source", [](const FrameTruth& f) { return !f.mixed_light; }});
  AddRanges("red gain", kGainBins, &FrameTruth::red_gain, &out);
  AddRanges("blue gain", kGainBins, &FrameTruth::blue_gain, &out);
  AddRanges("light", kLightBins, &FrameTruth::exposure, &out);
  return out;
}

// One table of CastRecallSection: the tags `scope` keeps.
std::string CastRecallTable(const Context& c, const std::function<bool(const TagTruth&)>& scope) {
  const bool calibrated = AnyCalibrated(c);
  Table rows;
  for (const FrameCondition& condition : CastAndLightConditions()) {
    const TagFilter keep = [&](const FrameTruth& f, const TagTruth& t) {
      return condition.has(f) && scope(t);
    };
    const auto tally = Count(c, keep);
    const Tally cal = CountCalibrated(c, keep);
    rows.push_back({condition.name, Grouped(tally[kChromaTag].tags),
                    RecallCell(c, tally, kChromaTag),
                    calibrated ? Percent(cal.hits, cal.tags) : "n/a",
                    RecallCell(c, tally, kAprilTag), RecallCell(c, tally, kAruco)});
  }
  return Markdown({"condition", "tags", c.info.names[kChromaTag] + " %", "calibrated %",
                   c.info.names[kAprilTag] + " %", c.info.names[kAruco] + " %"},
                  rows);
}

}  // namespace

std::string CastRecallSection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera) return "";
  std::ostringstream out;
  out << "### Recall per cast and light level\n\n"
      << "The camera's white-balance gains on linear red and blue (green's 1), each in "
      << Fixed(kMinCastGain, 1) << "–" << Fixed(kMaxCastGain, 1)
      << ", applied before the sensor clips; a quarter of the frames are lit by two sources of "
         "different colour, their cast blending across the frame. A frame's cast is the one at "
         "the card's centre: neutral when both gains lie within "
      << Fixed(100 * (kNeutralFactor - 1), 0)
      << " % of 1, otherwise warm (red "
         "over blue), cool (blue over red), green (both below 1) or magenta (both above), "
         "whichever leans furthest. Light: exposure times light level on the card, 1 for paper "
         "white at the encoding's white. Each detector against its own tag, both families, all "
         "prints; \"calibrated\" is ChromaTag with the config calibrated for each frame's print"
      << (AnyCalibrated(c) ? "" : " (not run)") << ".\n\n"
      << "**Tags of 30 px or more seen at up to 60°**\n\n"
      << CastRecallTable(c, Squarish) << "\n"
      << "**Tags of 50 px or more seen at up to 60°**\n\n"
      << CastRecallTable(c, Large) << "\n"
      << "**Every tag**\n\n"
      << CastRecallTable(c, [](const TagTruth&) { return true; });
  return out.str();
}

namespace {

// Pose errors against the truth of the tags `keep` keeps that the estimator
// `e` found: 0-2 the detectors (TagDetector::Pose), 3 ChromaTag from four
// corners (IPPE_SQUARE). Each estimator over the tags it found.
constexpr int kFourCornerChromaTag = kNumDetectors;

struct PoseErrors {
  std::vector<double> rotation_deg, translation_pct;
};

PoseErrors CollectPoseErrors(const Context& c, int e,
                             const std::function<bool(const TagTruth&)>& keep) {
  PoseErrors errors;
  for (const auto& r : c.records) {
    if (!r.truth.has_tags) continue;
    const int d = e == kFourCornerChromaTag ? kChromaTag : e;
    if (!c.info.active[d] || !keep(OwnTruth(r, d))) continue;
    const double rotation = e == kFourCornerChromaTag ? r.chromatag_four_corner_rotation_error_deg
                                                      : r.detectors[d].rotation_error_deg;
    const double translation = e == kFourCornerChromaTag
                                   ? r.chromatag_four_corner_translation_error_pct
                                   : r.detectors[d].translation_error_pct;
    if (std::isnan(rotation) || std::isnan(translation)) continue;
    errors.rotation_deg.push_back(rotation);
    errors.translation_pct.push_back(translation);
  }
  return errors;
}

}  // namespace

std::string PoseSection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera) return "";
  std::vector<std::pair<std::string, std::function<bool(const TagTruth&)>>> ranges;
  for (const Range& tilt : kTiltGroups) {
    ranges.push_back({"tilt " + tilt.name, [tilt](const TagTruth& t) {
                        return t.size_px >= 30 && tilt.Contains(t.view_angle_deg);
                      }});
  }
  for (const Range& size : kSizeGroups) {
    ranges.push_back({"size " + size.name, [size](const TagTruth& t) {
                        return size.Contains(t.size_px) && t.view_angle_deg <= 60;
                      }});
  }
  ranges.push_back({"≥ 30 px, ≤ 60°", Squarish});
  const int estimators[] = {kChromaTag, kFourCornerChromaTag, kAprilTag, kAruco};
  Table rows;
  for (const auto& [name, keep] : ranges) {
    std::vector<std::string> row = {name};
    for (int e : estimators) {
      const int d = e == kFourCornerChromaTag ? kChromaTag : e;
      if (!c.info.active[d]) {
        row.insert(row.end(), {"n/a", "n/a"});
        continue;
      }
      const PoseErrors errors = CollectPoseErrors(c, e, keep);
      row.push_back(Fixed(Percentile(errors.rotation_deg, 50), 2) + " / " +
                    Fixed(Percentile(errors.rotation_deg, 90), 2) + " (" +
                    Grouped(errors.rotation_deg.size()) + ")");
      row.push_back(Fixed(Percentile(errors.translation_pct, 50), 2) + " / " +
                    Fixed(Percentile(errors.translation_pct, 90), 2));
    }
    rows.push_back(row);
  }
  std::vector<std::string> header = {"range"};
  for (const std::string& name :
       {c.info.names[kChromaTag] + " (12 corners)", c.info.names[kChromaTag] + " (4 corners)",
        c.info.names[kAprilTag], c.info.names[kAruco]}) {
    header.push_back(name + ": rotation °");
    header.push_back("translation %");
  }
  return "### Pose against the truth\n\n"
         "Each detector's own tag, found, its pose as a user of the detector gets it, against the "
         "frame's true camera_from_tag (pinhole camera, no distortion; tag size one black square): "
         "the angle of the rotation between them in degrees, and the distance between the "
         "translations in % of the tag's distance, as median / 90th percentile (tags). ChromaTag "
         "(12 corners) is `EstimateTagPose` on the outer and inner ring corners; ChromaTag (4 "
         "corners) and OpenCV ArUco are OpenCV's `solvePnP` with `SOLVEPNP_IPPE_SQUARE` on the "
         "four outer corners (what ArUco's `estimatePoseSingleMarkers` does); AprilTag 3 is "
         "libapriltag's `estimate_tag_pose`. Tilt rows keep tags of 30 px or more, size rows "
         "tags seen at up to 60°.\n\n" +
         Markdown(header, rows);
}

namespace {

// The targets for washed-out prints: per print, up to 60 degrees of tilt.
void PrintTargets(const Context& c, const std::function<std::string(bool, bool)>& verdict,
                  Table* rows) {
  const bool april = c.info.active[kAprilTag];
  const bool calibrated = AnyCalibrated(c);
  auto keep = [](PrintKind print, const char* family, double lo, double hi) -> TagFilter {
    return [=](const FrameTruth& f, const TagTruth& t) {
      return f.print == print && f.family == family && t.size_px >= lo && t.size_px < hi &&
             UpTo60(t);
    };
  };
  auto cell = [&](const Tally& t) {
    return Percent(t.hits, t.tags) + " % (" + Grouped(t.tags) + ")";
  };
  auto add = [&](const std::string& what, const std::string& wanted, const Tally& ours,
                 const std::string& theirs, bool known, bool pass) {
    rows->push_back({what, wanted, cell(ours), theirs, verdict(known && ours.tags > 0, pass)});
  };
  const PrintKind iccv17 = PrintKind::kIccv17, press = PrintKind::kDefaultPress;
  {
    const auto mid = Count(c, keep(iccv17, "16h5", 30, kInf));
    const auto large = Count(c, keep(iccv17, "16h5", 70, kInf));
    const auto mid36 = Count(c, keep(iccv17, "36h11", 30, kInf));
    add("iccv17, 16h5: recall, ≥ 30 px at ≤ 60°", "≥ AprilTag 3's − 2 points", mid[kChromaTag],
        april ? cell(mid[kAprilTag]) : "n/a", april && mid[kAprilTag].tags > 0,
        mid[kChromaTag].Recall() >= mid[kAprilTag].Recall() - 0.02);
    add("iccv17, 16h5: recall, ≥ 70 px at ≤ 60°", "≥ 99.5 %", large[kChromaTag],
        april ? cell(large[kAprilTag]) : "n/a", true, large[kChromaTag].Recall() >= 0.995);
    add("iccv17, 36h11: recall, ≥ 30 px at ≤ 60°", "≥ 16h5's − 5 points", mid36[kChromaTag],
        "(16h5: " + cell(mid[kChromaTag]) + ")", mid[kChromaTag].tags > 0,
        mid36[kChromaTag].Recall() >= mid[kChromaTag].Recall() - 0.05);
    const Tally cal = CountCalibrated(c, keep(iccv17, "16h5", 30, kInf));
    add("iccv17 calibrated, 16h5: recall, ≥ 30 px at ≤ 60°", "≥ AprilTag 3's", cal,
        april ? cell(mid[kAprilTag]) : "n/a", april && calibrated && mid[kAprilTag].tags > 0,
        cal.Recall() >= mid[kAprilTag].Recall());
  }
  for (const Range& size : kSizeGroups) {
    const auto tally = Count(c, keep(press, "16h5", size.lo, size.hi));
    const bool small = size.hi <= 30;
    const double wanted = small ? 0.9 * tally[kAprilTag].Recall() : tally[kAprilTag].Recall();
    add("default-press, 16h5: recall, " + size.name + " at ≤ 60°",
        small ? "≥ 90 % of AprilTag 3's" : "≥ AprilTag 3's", tally[kChromaTag],
        april ? cell(tally[kAprilTag]) : "n/a", april && tally[kAprilTag].tags > 0,
        tally[kChromaTag].Recall() >= wanted);
  }
  if (calibrated) {
    int free_fp = 0, wrong = 0;
    for (const auto& r : c.records) {
      if (!r.calibrated.ran) continue;
      (r.truth.has_tags ? wrong : free_fp) +=
          r.truth.has_tags ? r.calibrated.score.wrong_ids : r.calibrated.score.false_positives;
    }
    rows->push_back(
        {"calibrated configs: false detections on tag-free frames (each config on "
         "every one) and wrong IDs",
         "0", Grouped(free_fp) + " and " + Grouped(wrong), "",
         verdict(c.tag_free > 0, free_fp == 0 && wrong == 0)});
  }
}

}  // namespace

std::string TargetsSection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera) return "";
  Table rows;
  const bool april = c.info.active[kAprilTag];
  auto verdict = [](bool known, bool pass) {
    return !known ? std::string("n/a") : pass ? std::string("pass") : std::string("**fail**");
  };
  for (const std::string& family : Families(c)) {
    auto tally = [&](double size_lo, double size_hi, double tilt_lo, double tilt_hi) {
      return Count(c, [&](const FrameTruth& f, const TagTruth& t) {
        return f.family == family && t.size_px >= size_lo && t.size_px < size_hi &&
               t.view_angle_deg > tilt_lo && t.view_angle_deg <= tilt_hi;
      });
    };
    const auto mid = tally(30, kInf, -1, 60), large = tally(70, kInf, -1, 60),
               steep = tally(70, kInf, 60, kInf), small = tally(0, 30, -1, kInf);
    auto recall = [&](const std::array<Tally, kNumDetectors>& t, int d) {
      return c.info.active[d] ? Percent(t[d].hits, t[d].tags) + " % (" + Grouped(t[d].tags) + ")"
                              : "n/a";
    };
    const double ct_mid = mid[kChromaTag].Recall(), at_mid = mid[kAprilTag].Recall();
    rows.push_back({family + ": recall, ≥ 30 px at ≤ 60°", "≥ AprilTag 3's",
                    recall(mid, kChromaTag), recall(mid, kAprilTag),
                    verdict(april && mid[kChromaTag].tags > 0, ct_mid >= at_mid)});
    rows.push_back({family + ": recall, ≥ 70 px at ≤ 60°", "≥ 99.5 %", recall(large, kChromaTag),
                    recall(large, kAprilTag),
                    verdict(large[kChromaTag].tags > 0, large[kChromaTag].Recall() >= 0.995)});
    rows.push_back({family + ": recall, ≥ 70 px at 60–75°", "≥ 95 %", recall(steep, kChromaTag),
                    recall(steep, kAprilTag),
                    verdict(steep[kChromaTag].tags > 0, steep[kChromaTag].Recall() >= 0.95)});
    rows.push_back({family + ": recall, < 30 px", "≥ 2/3 of AprilTag 3's",
                    recall(small, kChromaTag), recall(small, kAprilTag),
                    verdict(april && small[kChromaTag].tags > 0,
                            small[kChromaTag].Recall() >= small[kAprilTag].Recall() * 2.0 / 3.0)});
  }
  PrintTargets(c, verdict, &rows);
  // Pose: ChromaTag's median errors at most AprilTag 3's in every tilt group.
  for (const Range& tilt : kTiltGroups) {
    auto keep = [tilt](const TagTruth& t) {
      return t.size_px >= 30 && tilt.Contains(t.view_angle_deg);
    };
    const PoseErrors ct = CollectPoseErrors(c, kChromaTag, keep);
    const PoseErrors at = april ? CollectPoseErrors(c, kAprilTag, keep) : PoseErrors{};
    const double ct_r = Percentile(ct.rotation_deg, 50), at_r = Percentile(at.rotation_deg, 50);
    const double ct_t = Percentile(ct.translation_pct, 50),
                 at_t = Percentile(at.translation_pct, 50);
    rows.push_back({"pose, tilt " + tilt.name + " from 30 px: median rotation ° / translation %",
                    "≤ AprilTag 3's", Fixed(ct_r, 2) + " / " + Fixed(ct_t, 2),
                    april ? Fixed(at_r, 2) + " / " + Fixed(at_t, 2) : "n/a",
                    verdict(april && !ct.rotation_deg.empty() && !at.rotation_deg.empty(),
                            ct_r <= at_r && ct_t <= at_t)});
  }
  // Precision, false and wrong detections over all frames.
  std::array<int, kNumDetectors> tp{}, fp{}, free_fp{}, wrong{};
  std::array<std::vector<double>, kNumDetectors> corners, tagged_us, free_us;
  std::vector<double> tagged_alone_us, free_alone_us;
  for (const auto& r : c.records) {
    if (!std::isnan(r.chromatag_alone_us))
      (r.truth.has_tags ? tagged_alone_us : free_alone_us).push_back(r.chromatag_alone_us);
    for (int d = 0; d < kNumDetectors; ++d) {
      const DetectorRecord& dr = r.detectors[d];
      if (!dr.ran) continue;
      tp[d] += dr.score.found ? 1 : 0;
      fp[d] += dr.score.false_positives;
      wrong[d] += dr.score.wrong_ids;
      (r.truth.has_tags ? tagged_us : free_us)[d].push_back(dr.time_us);
      if (!r.truth.has_tags) free_fp[d] += dr.score.false_positives;
      if (dr.score.found) {
        corners[d].insert(corners[d].end(), dr.score.corner_error_px.begin(),
                          dr.score.corner_error_px.end());
      }
    }
  }
  auto apriltag = [&](const std::string& value) { return april ? value : std::string("n/a"); };
  rows.push_back({"precision (all frames)", "100 %", Percent(tp[0], tp[0] + fp[0], 2) + " %",
                  apriltag(Percent(tp[1], tp[1] + fp[1], 2) + " %"), verdict(true, fp[0] == 0)});
  rows.push_back({"false detections on tag-free frames", "0", Grouped(free_fp[0]),
                  apriltag(Grouped(free_fp[1])), verdict(c.tag_free > 0, free_fp[0] == 0)});
  rows.push_back({"wrong IDs (wrong family or ID on the tag)", "0", Grouped(wrong[0]),
                  apriltag(Grouped(wrong[1])), verdict(true, wrong[0] == 0)});
  rows.push_back({"corner error, median px", "(no bound set)", Fixed(Percentile(corners[0], 50), 2),
                  apriltag(Fixed(Percentile(corners[1], 50), 2)), "–"});
  const double tagged_median = Percentile(tagged_us[0], 50),
               free_median = Percentile(free_us[0], 50);
  rows.push_back({"median time, frames with tags", "≤ 100 µs", Fixed(tagged_median, 1) + " µs",
                  apriltag(Fixed(Percentile(tagged_us[1], 50), 0) + " µs"),
                  verdict(!tagged_us[0].empty(), tagged_median <= 100)});
  rows.push_back({"median time, tag-free frames", "≤ 30 µs", Fixed(free_median, 1) + " µs",
                  apriltag(Fixed(Percentile(free_us[1], 50), 0) + " µs"),
                  verdict(!free_us[0].empty(), free_median <= 30)});
  const bool alone = !tagged_alone_us.empty() || !free_alone_us.empty();
  if (alone) {
    rows.push_back({"median time, frames with tags, ChromaTag alone", "(not a target)",
                    Fixed(Percentile(tagged_alone_us, 50), 1) + " µs", "", "–"});
    rows.push_back({"median time, tag-free frames, ChromaTag alone", "(not a target)",
                    Fixed(Percentile(free_alone_us, 50), 1) + " µs", "", "–"});
  }
  return "### Targets\n\n"
         "ChromaTag against the targets on this set; AprilTag 3's value beside it (in brackets: "
         "tags counted). Tilt is the viewing angle; \"n/a\" where AprilTag 3 was not run "
         "(`--detectors chromatag`) or no tag fell in the range. Times are the timed loop's, on "
         "this machine under the load stated above. The time targets are judged on the detectors "
         "taking turns on each frame, so that each finds the caches as the others left them (a "
         "pipeline doing other work between frames)" +
         std::string(alone ? "; the rows \"ChromaTag alone\" time it again on the same frames "
                             "called one after another with nothing in between (a thread that "
                             "only detects), for comparison"
                           : "") +
         ".\n\n" +
         Markdown(
             {"target", "wanted", c.info.names[kChromaTag], c.info.names[kAprilTag], "verdict"},
             rows);
}

std::string MissTable(const Context& c) {
  constexpr int kGroups = sizeof(kSizeGroups) / sizeof(kSizeGroups[0]);
  std::array<int, kGroups> tags{}, misses{};
  // By stage (kNumStages: reported wrongly), and by (stage, reason).
  std::vector<std::array<int, kGroups>> by_stage(kNumStages + 1);
  std::map<std::pair<int, std::string>, std::array<int, kGroups>> by_reason;
  int total = 0;
  for (const auto& r : c.records) {
    if (!r.truth.has_tags) continue;
    int g = 0;
    while (g + 1 < kGroups && !kSizeGroups[g].Contains(r.truth.chromatag.size_px)) ++g;
    ++tags[g];
    const MissCause& miss = r.chromatag_miss;
    if (r.detectors[kChromaTag].score.found || !miss.analysed) continue;
    ++misses[g];
    ++total;
    ++by_stage[std::clamp(miss.stage, 0, kNumStages)][g];
    ++by_reason[{miss.stage, miss.reason}][g];
  }
  auto row = [&](const std::string& label, const std::array<int, kGroups>& counts) {
    std::vector<std::string> cells = {label};
    int sum = 0;
    for (int g = 0; g < kGroups; ++g) {
      cells.push_back(Grouped(counts[g]));
      sum += counts[g];
    }
    cells.push_back(Grouped(sum));
    cells.push_back(Percent(sum, total));
    return cells;
  };
  std::vector<std::string> header = {"failed at"};
  for (const Range& group : kSizeGroups) header.push_back(group.name);
  header.insert(header.end(), {"all", "% of misses"});
  Table stages = {row("tags", tags), row("missed", misses)};
  stages[0].back() = "";  // Tags are not misses.
  for (int s = 0; s <= kNumStages; ++s) {
    const bool any = std::any_of(by_stage[s].begin(), by_stage[s].end(), [](int n) { return n; });
    if (s < kNumStages || any) stages.push_back(row(MissStageName(s), by_stage[s]));
  }
  Table reasons;
  for (const auto& [key, counts] : by_reason) {
    reasons.push_back(row(MissStageName(key.first) + ": " + key.second, counts));
  }
  header[0] = "stage: reason";
  std::vector<std::string> stage_header = header;
  stage_header[0] = "failed at";
  std::ostringstream out;
  out << "(b) Frames with tags in which ChromaTag missed its tag, by size group (ChromaTag's "
         "size), assigned exactly: the detector is run again, untimed, with its rejected "
         "candidates reported, and the miss goes to the deepest stage (then the latest reason "
         "in the detector's list) among the candidates whose seed or centre lies within the "
         "tag's outer border (black square and quiet zone); to FindADiff (\"no candidate\") "
         "when none started there; to \"reported\" when a detection on the tag had the wrong "
         "family or ID or corners too far off.\n\n"
      << Markdown(stage_header, stages) << "\n"
      << Markdown(header, reasons);
  return out.str();
}

}  // namespace chromatag::bench
