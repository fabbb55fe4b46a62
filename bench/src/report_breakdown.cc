// The report's breakdowns: recall per family by size and tilt, per print,
// per condition and per cast and light level, pose, and Table 4(b) from the
// miss analysis.
#include <algorithm>
#include <cmath>
#include <cstdio>
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

namespace {

// The configs calibrated for each print, against the defaults.
std::string CalibratedConfigsTable(const Context& c) {
  std::ostringstream out;
  Table configs;
  for (const auto& [print, o] : c.info.calibrated) {
    configs.push_back({print, Fixed(o.adiff_thresh, 1), Fixed(o.border_thresh, 1),
                       Fixed(o.min_decision_margin, 1), Fixed(o.max_green_a, 1),
                       o.two_step_rises ? "on" : "off"});
  }
  out << "The calibrated configs (the defaults: " << Fixed(DetectorOptions{}.adiff_thresh, 1)
      << ", " << Fixed(DetectorOptions{}.border_thresh, 1) << ", "
      << Fixed(DetectorOptions{}.min_decision_margin, 1) << ", "
      << Fixed(DetectorOptions{}.max_green_a, 1) << ", "
      << (DetectorOptions{}.two_step_rises ? "on" : "off") << "):\n\n"
      << Markdown({"print", "ADiffThresh", "BorderThresh", "min decision margin", "max green a*",
                   "two-step rises"},
                  configs)
      << "\n";
  return out.str();
}

// One print's recall by size and tilt, each family with its own columns.
std::string PrintRecallTable(const Context& c, PrintKind print, bool calibrated) {
  std::ostringstream out;
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
  return out.str();
}

}  // namespace

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
  if (!c.info.calibrated.empty()) out << CalibratedConfigsTable(c);
  for (int k = 0; k < kNumPrintKinds; ++k)
    out << PrintRecallTable(c, static_cast<PrintKind>(k), calibrated);
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

namespace {

// The ranges the pose tables break the tags into: tilt groups (30 px and
// more), size groups (up to 60 degrees), and both.
std::vector<std::pair<std::string, std::function<bool(const TagTruth&)>>> PoseRanges() {
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
  return ranges;
}

}  // namespace

CovarianceTally CalibrationOfPoses(const Context& c, int d,
                                   const std::function<bool(const TagTruth&)>& keep) {
  CovarianceTally tally;
  for (const auto& r : c.records) {
    const DetectorRecord& out = r.detectors[d];
    const TagTruth& own = d == kChromaTag ? r.truth.chromatag : r.truth.apriltag;
    if (r.truth.has_tags && out.ran && !std::isnan(out.pose_nees) && keep(own))
      tally.Add(out.pose_z, out.pose_nees);
  }
  return tally;
}

std::string PoseUncertaintySection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera || !c.info.active[kChromaTag]) return "";
  const auto table = [&](int d) {
    Table rows;
    for (const auto& [name, keep] : PoseRanges()) {
      const CovarianceTally p = CalibrationOfPoses(c, d, keep);
      std::vector<std::string> row = {name, Grouped(p.poses())};
      for (int axis = 0; axis < 6; ++axis) row.push_back(Fixed(p.Spread(axis), 2));
      row.push_back(p.poses() > 0 ? Fixed(100.0 * p.Coverage(), 1) + " %" : "–");
      rows.push_back(row);
    }
    return Markdown({"range", "poses", "x", "y", "z", "rot x", "rot y", "rot z", "in 95 %"}, rows);
  };
  std::string apriltag;
  if (c.info.active[kAprilTag]) {
    char sigma[32];
    std::snprintf(sigma, sizeof sigma, "%.1f", kAssumedCornerSigmaPx);
    apriltag =
        std::string(
            "\nAprilTag 3's own poses, with the covariance its user would have to "
            "assume: ChromaTag's for AprilTag 3's four corners taken as independent, ") +
        sigma +
        " px per coordinate (about its median corner error, 0.76 px, rounded up; "
        "`AssumedPoseCovariance`). Another figure divides every spread by the same factor "
        "and keeps their ratios: one figure cannot fit every axis, size and tilt. AprilTag's "
        "square found too small (its outward offset above) puts the tag too far, a bias that "
        "no covariance of zero-mean noise covers: it shows in z.\n\n" +
        table(kAprilTag);
  }
  return "### Pose uncertainty against the truth\n\n"
         "ChromaTag's pose covariance (`TagPose::covariance`, from the detector's corner "
         "covariance) tested on the tags of the table above: for each axis (translation x, y, z, "
         "then the small rotation about the camera's x, y, z that takes the estimate to the "
         "truth), the root mean square of the error over its predicted standard deviation "
         "(1 when the covariance is right; above 1 it claims too much), and the share of poses "
         "whose whole error lies inside the covariance's 95 % ellipsoid (a squared Mahalanobis "
         "distance within 12.59, chi-square with six degrees of freedom). AprilTag 3's "
         "`estimate_tag_pose` gives no covariance, only the object-space error of its fit "
         "(apriltag_ros publishes zeros): a user has to assume one (the second table).\n\n" +
         table(kChromaTag) + apriltag;
}

std::string PoseSection(const Context& c) {
  if (c.info.dataset.kind != DatasetKind::kCamera) return "";
  const auto ranges = PoseRanges();
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
