// The comparison's report: Markdown tables, PNG figures and a per-frame CSV,
// all computed from the frame records of one run.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "chromatag/bench/comparison.h"
#include "chromatag/bench/plot.h"
#include "report_util.h"

namespace chromatag::bench {
namespace {
// Bins of Figure 9: tag size (sqrt of the black square's area) and viewing angle.
const Bins kSizeBins{10.0, 10.0, 20};  // 10-210 px.
const Bins kAngleBins{0.0, 5.0, 16};   // 0-80 degrees.
const Bins kMapSizeBins{10.0, 20.0, 10};
const Bins kMapAngleBins{0.0, 10.0, 8};
// Curves skip bins with fewer tags than this.
constexpr int kMinTrialsPerPoint = 5;

const std::array<std::array<double, 3>, kNumDetectors> kColors = {
    {{0.84, 0.15, 0.16}, {0.12, 0.47, 0.71}, {0.17, 0.63, 0.17}}};

std::string DatasetSection(const Context& c) {
  std::array<int, kNumConditions> per_condition{};
  std::map<std::string, int> per_family;
  std::vector<double> sizes, angles;
  for (const auto& r : c.records) {
    if (!r.truth.has_tags) continue;
    ++per_condition[static_cast<int>(r.truth.condition)];
    ++per_family[r.truth.family];
    for (const TagTruth* t : {&r.truth.chromatag, &r.truth.apriltag}) {
      sizes.push_back(t->size_px);
      angles.push_back(t->view_angle_deg);
    }
  }
  const DatasetOptions& o = c.info.dataset;
  std::ostringstream families;
  for (const auto& [name, count] : per_family) {
    families << (families.tellp() > 0 ? ", " : "") << count << " " << name;
  }
  const bool camera = o.kind == DatasetKind::kCamera;
  std::ostringstream out;
  out << "Data set \"" << DatasetKindName(o.kind) << "\": " << c.records.size() << " frames of "
      << o.width << "x" << o.height << " (seed " << o.seed << "): " << c.tagged
      << " with a ChromaTag and its AprilTag twin side by side (" << families.str() << "; "
      << per_condition[0]
      << (camera ? " white-balanced (a neutral cast, one light source), " : " WB, ")
      << per_condition[1] << (camera ? " with a colour cast or mixed light), " : " NWB), ")
      << c.tag_free << " with no tag. Tag size (square root of the black square's area) "
      << Fixed(Percentile(sizes, 0), 0) << "–" << Fixed(Percentile(sizes, 100), 0) << " px, median "
      << Fixed(Percentile(sizes, 50), 0) << " px; viewing angle " << Fixed(Percentile(angles, 0), 0)
      << "–" << Fixed(Percentile(angles, 100), 0) << "°, median "
      << Fixed(Percentile(angles, 50), 0) << "°. Backgrounds: " << c.info.photos.size()
      << " photographs from Debian's opencv-doc. Four of the frames, with the truth in white and "
         "the detections in red (ChromaTag), blue (AprilTag) and green (ArUco)"
      << (c.info.active[kAprilTag] ? "" : "; this run had ChromaTag only") << ":\n\n"
      << "![example frames](examples.jpg)\n";
  return out.str();
}

std::string FpsTable(const Context& c) {
  std::array<std::array<std::vector<double>, 4>, kNumDetectors>
      times;  // all, found, none, tag-free
  for (const auto& r : c.records) {
    for (int d = 0; d < kNumDetectors; ++d) {
      const DetectorRecord& dr = r.detectors[d];
      times[d][0].push_back(dr.time_us);
      if (dr.score.found) times[d][1].push_back(dr.time_us);
      if (dr.num_found == 0) times[d][2].push_back(dr.time_us);
      if (!r.truth.has_tags) times[d][3].push_back(dr.time_us);
    }
  }
  std::array<std::array<double, 4>, kNumDetectors> fps{};
  Table rows;
  for (int d = 0; d < kNumDetectors; ++d) {
    if (!c.info.active[d]) continue;
    std::vector<std::string> row = {c.info.names[d]};
    for (int k = 0; k < 4; ++k) {
      fps[d][k] = times[d][k].empty() ? kNaN : 1e6 / Mean(times[d][k]);
      row.push_back(Grouped(fps[d][k]) + " (" + Grouped(times[d][k].size()) + ")");
    }
    row.push_back(Fixed(Mean(times[d][0]), 1));
    row.push_back(Fixed(Percentile(times[d][0], 50), 1));
    row.push_back(Fixed(Percentile(times[d][0], 99), 1));
    rows.push_back(row);
  }
  for (int d : {kAprilTag, kAruco}) {
    if (!c.info.active[d]) continue;
    std::vector<std::string> row = {"ChromaTag ÷ " + c.info.names[d]};
    for (int k = 0; k < 4; ++k) row.push_back(Fixed(fps[kChromaTag][k] / fps[d][k], 1) + "×");
    row.insert(row.end(), {"", "", ""});
    rows.push_back(row);
  }
  return "### Table 1: frames per second\n\n"
         "One thread, 1 / (mean time per frame); in brackets the number of frames averaged. "
         "\"Tag found\" counts the frames where the detector found its own tag (the paper's true "
         "positives), \"no detection\" the frames where it reported nothing.\n\n" +
         Markdown({"detector", "all frames", "tag found", "no detection", "tag-free frames",
                   "mean µs", "median µs", "99th pct µs"},
                  rows);
}

std::string StageTable(const Context& c) {
  std::array<std::array<double, kNumStages>, 3> sums{};  // found, tag-free, all
  std::array<int, 3> counts{};
  std::array<double, 3> totals{};
  for (const auto& r : c.records) {
    const bool groups[3] = {r.detectors[kChromaTag].score.found, !r.truth.has_tags, true};
    for (int g = 0; g < 3; ++g) {
      if (!groups[g]) continue;
      ++counts[g];
      for (int s = 0; s < kNumStages; ++s) sums[g][s] += r.chromatag_summary.stage_time_us[s];
      totals[g] += r.chromatag_summary.total_time_us;
    }
  }
  Table rows;
  for (int s = 0; s < kNumStages; ++s) {
    std::vector<std::string> row = {StageName(static_cast<Stage>(s))};
    for (int g = 0; g < 3; ++g) {
      const double mean = counts[g] ? sums[g][s] / counts[g] : kNaN;
      const double share = counts[g] && totals[g] > 0 ? 100.0 * sums[g][s] / totals[g] : kNaN;
      row.push_back(Fixed(mean, 1) + " (" + Fixed(share, 0) + " %)");
    }
    rows.push_back(row);
  }
  std::vector<std::string> total = {"total (detector's own clock)"};
  for (int g = 0; g < 3; ++g) total.push_back(Fixed(counts[g] ? totals[g] / counts[g] : kNaN, 1));
  rows.push_back(total);
  return "### Table 2: ChromaTag time per stage\n\n"
         "Mean µs per frame (share of the detector's total), from a pass of its own with each "
         "stage timed (`time_stages`: the clock read around each candidate's stages adds a few "
         "per cent, which Table 1's times do not carry). The paper reports frames with a "
         "detection (its Table 2: 0.52, 0.03, 0.08, 0.74, 0.04 ms on a 3.5 GHz Ivy Bridge).\n\n" +
         Markdown({"stage", "frames with the tag found (" + Grouped(counts[0]) + ")",
                   "tag-free frames (" + Grouped(counts[1]) + ")",
                   "all frames (" + Grouped(counts[2]) + ")"},
                  rows);
}

std::string PrecisionRecallTable(const Context& c) {
  Table rows;
  for (int d = 0; d < kNumDetectors; ++d) {
    if (!c.info.active[d]) continue;
    for (int condition = 0; condition <= kNumConditions; ++condition) {
      int frames = 0, tp = 0, fp = 0;
      for (const auto& r : c.records) {
        if (!r.truth.has_tags) continue;
        if (condition < kNumConditions && static_cast<int>(r.truth.condition) != condition)
          continue;
        ++frames;
        tp += r.detectors[d].score.found ? 1 : 0;
        fp += r.detectors[d].score.false_positives;
      }
      rows.push_back({c.info.names[d],
                      condition < kNumConditions
                          ? ConditionName(static_cast<ColorCondition>(condition))
                          : "both",
                      Grouped(frames), Grouped(tp), Grouped(fp), Grouped(frames - tp),
                      Percent(tp, tp + fp), Percent(tp, frames)});
    }
  }
  return "### Table 3: precision and recall\n\n"
         "Frames with tags only (as in the paper, whose frames all held tags). A true positive has "
         "the right family and ID and an intersection over union of at least 0.5 with the true "
         "black square "
         "of the detector's own tag; any other detection, including a second report of the same "
         "tag, is a false positive.\n\n" +
         Markdown({"detector", "colour", "frames", "TP", "FP", "FN", "precision %", "recall %"},
                  rows);
}

std::string FailureTable(const Context& c) {
  // (a) Candidates per frame and where they were rejected.
  std::array<double, 2> seeds{};
  std::array<std::array<double, kNumStages>, 2> rejected{};
  std::array<int, 2> frames{};
  double fast = 0, detections = 0;
  for (const auto& r : c.records) {
    const int g = r.truth.has_tags ? 0 : 1;
    ++frames[g];
    seeds[g] += r.chromatag_summary.seeds;
    fast += r.chromatag_summary.fast_path_detections;
    detections += r.detectors[kChromaTag].num_found;
    for (int s = 0; s < kNumStages; ++s) rejected[g][s] += r.chromatag_summary.rejected[s];
  }
  Table a;
  a.push_back({"candidates (seeds handed to InitialScan)",
               Fixed(frames[0] ? seeds[0] / frames[0] : kNaN, 2),
               Fixed(frames[1] ? seeds[1] / frames[1] : kNaN, 2), ""});
  a.push_back({"detections by the fast path (quads from InitialScan's scans, no BuildPolygon)", "",
               "", Percent(fast, detections) + " % of detections"});
  for (int s = 0; s < kNumStages; ++s) {
    a.push_back({"rejected by " + std::string(StageName(static_cast<Stage>(s))),
                 Fixed(frames[0] ? rejected[0][s] / frames[0] : kNaN, 2),
                 Fixed(frames[1] ? rejected[1][s] / frames[1] : kNaN, 2),
                 s == 0 ? "(prefilter rises not confirmed)"
                        : Percent(rejected[0][s] + rejected[1][s], seeds[0] + seeds[1])});
  }
  std::ostringstream out;
  out << "### Table 4: where ChromaTag candidates fail\n\n"
      << "(a) Candidates per frame and the stage that rejected them (the detector's own counters; "
         "last column: share of all candidates).\n\n"
      << Markdown({"", "per frame with tags", "per tag-free frame", "% of candidates"}, a) << "\n"
      << MissTable(c);
  return out.str();
}

// Recall in a few broad ranges (the paper's reading of Figure 9: similar
// recall above about 70 px).
std::string RecallSummary(const Context& c) {
  struct Range {
    std::string name;
    bool by_size;
    double lo, hi;
  };
  const Range ranges[] = {{"size < 30 px", true, 0, 30},
                          {"size 30–70 px", true, 30, 70},
                          {"size ≥ 70 px", true, 70, 1e9},
                          {"angle < 45°", false, 0, 45},
                          {"angle 45–60°", false, 45, 60},
                          {"angle ≥ 60°", false, 60, 1e9},
                          {"size ≥ 70 px, angle < 60°", true, 70, 1e9}};
  Table rows;
  for (size_t k = 0; k < sizeof(ranges) / sizeof(ranges[0]); ++k) {
    const Range& range = ranges[k];
    const bool also_angle = k == sizeof(ranges) / sizeof(ranges[0]) - 1;
    std::vector<std::string> row = {range.name};
    std::array<int, kNumDetectors> tags{}, hits{};
    for (const auto& r : c.records) {
      if (!r.truth.has_tags) continue;
      for (int d = 0; d < kNumDetectors; ++d) {
        const TagTruth& t = OwnTruth(r, d);
        const double v = range.by_size ? t.size_px : t.view_angle_deg;
        if (v < range.lo || v >= range.hi || (also_angle && t.view_angle_deg >= 60)) continue;
        ++tags[d];
        hits[d] += r.detectors[d].score.found ? 1 : 0;
      }
    }
    row.push_back(Grouped(tags[kChromaTag]));
    for (int d = 0; d < kNumDetectors; ++d) {
      row.push_back(c.info.active[d] ? Percent(hits[d], tags[d]) : "n/a");
    }
    rows.push_back(row);
  }
  return Markdown({"range", "ChromaTags (AprilTags: about as many)", c.info.names[0] + " recall %",
                   c.info.names[1] + " recall %", c.info.names[2] + " recall %"},
                  rows);
}

struct Curves {
  std::vector<RecallCurve> size, angle;
  std::vector<RecallMap> map;
};

Curves ComputeCurves(const Context& c) {
  Curves curves;
  for (int d = 0; d < kNumDetectors; ++d) {
    curves.size.emplace_back(kSizeBins);
    curves.angle.emplace_back(kAngleBins);
    curves.map.emplace_back(kMapSizeBins, kMapAngleBins);
  }
  for (const auto& r : c.records) {
    if (!r.truth.has_tags) continue;
    for (int d = 0; d < kNumDetectors; ++d) {
      const TagTruth& t = OwnTruth(r, d);
      const bool hit = r.detectors[d].score.found;
      curves.size[d].Add(t.size_px, hit);
      curves.angle[d].Add(t.view_angle_deg, hit);
      curves.map[d].Add(t.size_px, t.view_angle_deg, hit);
    }
  }
  return curves;
}

Series CurveSeries(const RecallCurve& curve, const std::string& name, int d) {
  Series s;
  s.name = name;
  s.rgb = kColors[d];
  for (int i = 0; i < curve.bins.count; ++i) {
    s.x.push_back(curve.bins.Centre(i));
    s.y.push_back(curve.trials[i] >= kMinTrialsPerPoint ? curve.Recall(i) : kNaN);
  }
  return s;
}

bool WriteMap(const Context& c, const RecallMap& map, const std::string& title,
              const std::string& file) {
  HeatMap heat;
  heat.title = title;
  heat.x_label = "tag size (square root of the black square's area), px";
  heat.y_label = "viewing angle, degrees";
  for (int i = 0; i <= map.x_bins.count; ++i) heat.x_edges.push_back(map.x_bins.Edge(i));
  for (int i = 0; i <= map.y_bins.count; ++i) heat.y_edges.push_back(map.y_bins.Edge(i));
  heat.values.resize(map.y_bins.count);
  heat.counts.resize(map.y_bins.count);
  for (int y = 0; y < map.y_bins.count; ++y) {
    for (int x = 0; x < map.x_bins.count; ++x) {
      heat.values[y].push_back(map.Trials(x, y) >= kMinTrialsPerPoint ? map.Recall(x, y) : kNaN);
      heat.counts[y].push_back(map.Trials(x, y));
    }
  }
  return WriteHeatMap(heat, c.out_dir + "/" + file, c.error);
}

// Figures 9a to 9c (and AprilTag's map) as PNG files in the output folder.
bool WriteFigures(const Context& c, const Curves& curves) {
  LinePlot size_plot;
  size_plot.title = "Figure 9a: recall against tag size";
  size_plot.x_label = "tag size (square root of the black square's area), px";
  size_plot.y_label = "recall";
  size_plot.x_min = 0, size_plot.x_max = 210, size_plot.x_tick = 30;
  size_plot.y_min = 0, size_plot.y_max = 1, size_plot.y_tick = 0.1;
  LinePlot angle_plot = size_plot;
  angle_plot.title = "Figure 9b: recall against viewing angle";
  angle_plot.x_label = "viewing angle (tag normal to camera direction), degrees";
  angle_plot.x_max = 80, angle_plot.x_tick = 10;
  for (int d = 0; d < kNumDetectors; ++d) {
    if (!c.info.active[d]) continue;
    size_plot.series.push_back(CurveSeries(curves.size[d], c.info.names[d], d));
    angle_plot.series.push_back(CurveSeries(curves.angle[d], c.info.names[d], d));
  }
  return WriteLinePlot(size_plot, c.out_dir + "/fig9a_recall_vs_size.png", c.error) &&
         WriteLinePlot(angle_plot, c.out_dir + "/fig9b_recall_vs_angle.png", c.error) &&
         WriteMap(c, curves.map[kChromaTag], "Figure 9c: ChromaTag recall, size x angle",
                  "fig9c_chromatag_size_angle.png") &&
         (!c.info.active[kAprilTag] ||
          WriteMap(c, curves.map[kAprilTag], "AprilTag 3 recall, size x angle",
                   "fig9c_apriltag_size_angle.png"));
}

// Recall per bin of one curve set (size or angle), each detector a column.
std::string CurveTable(const Context& c, const std::vector<RecallCurve>& set,
                       const std::string& unit) {
  Table rows;
  for (int i = 0; i < set[0].bins.count; ++i) {
    if (set[0].trials[i] == 0) continue;
    const bool last = i == set[0].bins.count - 1;
    std::vector<std::string> row = {Fixed(set[0].bins.Edge(i), 0) +
                                        (last ? "+" : "–" + Fixed(set[0].bins.Edge(i + 1), 0)) +
                                        " " + unit,
                                    Grouped(set[0].trials[i])};
    for (int d = 0; d < kNumDetectors; ++d) {
      row.push_back(c.info.active[d] ? Fixed(100.0 * set[d].Recall(i), 1) : "n/a");
    }
    rows.push_back(row);
  }
  return Markdown(
      {"bin", "tags", c.info.names[0] + " %", c.info.names[1] + " %", c.info.names[2] + " %"},
      rows);
}

bool FigureSection(const Context& c, std::string* section) {
  const Curves curves = ComputeCurves(c);
  if (!WriteFigures(c, curves)) return false;
  std::ostringstream out;
  out << "### Figure 9: recall against tag size and viewing angle\n\n"
      << "Tag size is the square root of the black square's area in the image; the viewing angle "
         "is between the tag's normal and the direction from its centre to the camera (the "
         "paper's definitions). Each detector against its own tag; bins with fewer than "
      << kMinTrialsPerPoint << " tags are left out of the plots.\n\n"
      << "![recall against size](fig9a_recall_vs_size.png)\n"
      << "![recall against angle](fig9b_recall_vs_angle.png)\n"
      << "![ChromaTag recall over size and angle](fig9c_chromatag_size_angle.png)\n"
      << (c.info.active[kAprilTag]
              ? "![AprilTag recall over size and angle](fig9c_apriltag_size_angle.png)\n"
              : "")
      << "\n"
      << RecallSummary(c) << "\n"
      << "<details><summary>Recall per size bin</summary>\n\n"
      << CurveTable(c, curves.size, "px") << "\n</details>\n\n"
      << "<details><summary>Recall per angle bin</summary>\n\n"
      << CurveTable(c, curves.angle, "°") << "\n</details>\n";
  *section = out.str();
  return true;
}

// One detector's row of the corner table: its corners against the truth.
std::vector<std::string> CornerRow(const Context& c, int d) {
  std::vector<double> errors, large;
  cv::Point2d offset;
  double radial = 0.0;
  int found = 0, within3 = 0;
  for (const auto& r : c.records) {
    const FrameScore& s = r.detectors[d].score;
    if (!s.found) continue;
    ++found;
    offset += s.mean_offset_px;
    radial += s.mean_radial_offset_px;
    for (double e : s.corner_error_px) {
      errors.push_back(e);
      if (OwnTruth(r, d).size_px >= 50) large.push_back(e);
      within3 += e <= 3.0 ? 1 : 0;
    }
  }
  if (found) offset /= found, radial /= found;
  return {c.info.names[d],
          Grouped(found),
          Fixed(Percentile(errors, 50), 2),
          Fixed(Percentile(errors, 90), 2),
          Fixed(Percentile(large, 50), 2),
          Fixed(Percentile(large, 90), 2),
          Percent(within3, errors.size()),
          found ? "(" + Fixed(offset.x, 2) + ", " + Fixed(offset.y, 2) + ")" : "–",
          Fixed(found ? radial : kNaN, 2)};
}

// ChromaTag's inner ring corners (FrameScore::inner_corner_error_px).
std::vector<std::string> InnerRingRow(const Context& c) {
  std::vector<double> errors, large;
  int found = 0, within3 = 0;
  for (const auto& r : c.records) {
    const FrameScore& s = r.detectors[kChromaTag].score;
    if (!s.found || s.inner_corner_error_px.empty()) continue;
    ++found;
    for (double e : s.inner_corner_error_px) {
      errors.push_back(e);
      if (OwnTruth(r, kChromaTag).size_px >= 50) large.push_back(e);
      within3 += e <= 3.0 ? 1 : 0;
    }
  }
  return {c.info.names[kChromaTag] + ", inner rings",
          Grouped(found),
          Fixed(Percentile(errors, 50), 2),
          Fixed(Percentile(errors, 90), 2),
          Fixed(Percentile(large, 50), 2),
          Fixed(Percentile(large, 90), 2),
          Percent(within3, errors.size()),
          "–",
          "–"};
}

std::string CornerTable(const Context& c) {
  Table rows;
  for (int d = 0; d < kNumDetectors; ++d) {
    if (c.info.active[d]) rows.push_back(CornerRow(c, d));
  }
  if (c.info.active[kChromaTag]) rows.push_back(InnerRingRow(c));
  return "### Corner error\n\n"
         "Distance between each detected corner of the black square and the ground truth, over "
         "every true positive, in pixels. All three are put into spec section 7's conventions "
         "first: AprilTag's corners reordered from its counter-clockwise, bottom-left-first order "
         "and moved by -0.5 px (libapriltag puts pixel centres at +0.5); ArUco's turned by 180° "
         "(OpenCV 4.6 stores the AprilTag dictionaries turned, opencv/opencv-python#1195). The "
         "mean offset would show a remaining convention mismatch; the outward offset is negative "
         "when the square is found too small: after blur in linear light and the camera's gamma "
         "curve (as in a real camera), an edge's encoded halfway level lies inside the true edge, "
         "and a detector that takes that level finds the square too small. ChromaTag reports its "
         "corners where the black ring's width says the edges lie (docs/pose.md). The paper: "
         "94.4 % of ChromaTag's and 89.1 % of AprilTag's corners within 3 px of hand labels. "
         "The last row is ChromaTag's eight inner ring corners (green/black and red/green), "
         "against where the true black square's homography puts them.\n\n" +
         Markdown({"detector", "tags found", "median px", "90th pct px", "median px, ≥ 50 px tags",
                   "90th pct px, ≥ 50 px tags", "% within 3 px", "mean offset (x, y) px",
                   "mean outward offset px"},
                  rows);
}

// One detector's (or the calibrated configs') false detections, on tag-free
// frames and on frames with tags; of the latter, those on the other tag, wrong
// IDs and duplicates.
struct FalseCounts {
  int free = 0, free_frames_hit = 0, tagged = 0, on_other = 0, wrong = 0, duplicates = 0;
  void Add(const FrameTruth& truth, const FrameScore& s) {
    if (!truth.has_tags) {
      free += s.false_positives;
      free_frames_hit += s.false_positives > 0 ? 1 : 0;
      return;
    }
    tagged += s.false_positives;
    on_other += s.false_on_other_tag;
    wrong += s.wrong_ids;
    duplicates += s.duplicates;
  }
};

std::string FalseDetectionTable(const Context& c) {
  Table rows;
  auto add = [&](const std::string& name, const FalseCounts& n) {
    rows.push_back({name, Grouped(c.tag_free), Grouped(n.free),
                    Fixed(c.tag_free ? static_cast<double>(n.free) / c.tag_free : kNaN, 4),
                    Percent(n.free_frames_hit, c.tag_free, 2), Grouped(n.tagged),
                    Grouped(n.on_other), Grouped(n.wrong), Grouped(n.duplicates)});
  };
  for (int d = 0; d < kNumDetectors; ++d) {
    if (!c.info.active[d]) continue;
    FalseCounts counts;
    for (const auto& r : c.records) counts.Add(r.truth, r.detectors[d].score);
    add(c.info.names[d], counts);
  }
  FalseCounts calibrated;
  bool any = false;
  for (const auto& r : c.records) {
    if (!r.calibrated.ran) continue;
    any = true;
    calibrated.Add(r.truth, r.calibrated.score);
  }
  if (any) add(c.info.names[kChromaTag] + ", calibrated configs", calibrated);
  return "### False detections\n\n"
         "On the tag-free frames every detection is false. On frames with tags, a detection is "
         "false unless it is the first with the right family and ID on the detector's own tag; "
         "of those, the last columns count the ones lying on the other kind of tag (AprilTag or "
         "ArUco reading the ChromaTag's black square as a code, or the reverse), the ones on the "
         "own tag with a wrong family or ID, and duplicates: the own tag reported again with the "
         "right ID. The calibrated configs run on the frames of their print and each on every "
         "tag-free frame.\n\n" +
         Markdown({"detector", "tag-free frames", "false detections", "per tag-free frame",
                   "% of tag-free frames with any", "false detections on frames with tags",
                   "of which on the other tag", "wrong IDs", "duplicates"},
                  rows);
}

// frames.csv's first line: the column names.
void WriteCsvHeader(std::ostream& out) {
  out << "index,condition,has_tags,id,photo,exposure,blur_sigma_px,motion_blur_px,noise_sigma,"
         "jpeg_quality,chromatag_size_px,chromatag_angle_deg,apriltag_size_px,apriltag_angle_deg,"
         "set,family,quiet_zone_cells,cast,gradient,tone_gamma,print_chroma,shot_snr,read_noise,"
         "bayer,print,red_gain,blue_gain,mixed_light";
  const char* keys[] = {"chromatag", "apriltag", "aruco"};
  for (const char* key : keys) {
    out << "," << key << "_us," << key << "_found," << key << "_false," << key << "_duplicates,"
        << key << "_corner_px," << key << "_outward_px";
  }
  out << ",chromatag_alone_us,calibrated_found,calibrated_false,calibrated_duplicates";
  for (int s = 0; s < kNumStages; ++s) out << ",us_" << StageName(static_cast<Stage>(s));
  for (int s = 0; s < kNumStages; ++s) out << ",rejected_" << StageName(static_cast<Stage>(s));
  out << ",seeds,chromatag_miss_stage,chromatag_miss_reason";
  for (const char* key : keys) out << "," << key << "_rotation_deg," << key << "_translation_pct";
  out << ",chromatag_4_corners_rotation_deg,chromatag_4_corners_translation_pct";
  for (const char* axis : {"x", "y", "z", "rx", "ry", "rz"}) out << ",chromatag_pose_z_" << axis;
  out << ",chromatag_pose_nees\n";
}

// How the frame was made.
void WriteTruthColumns(std::ostream& out, const FrameTruth& t) {
  out << t.index << "," << ConditionName(t.condition) << "," << t.has_tags << ","
      << (t.has_tags ? t.chromatag.id : -1) << "," << t.photo << "," << t.exposure << ","
      << t.blur_sigma_px << "," << t.motion_blur_px << "," << t.noise_sigma << "," << t.jpeg_quality
      << "," << t.chromatag.size_px << "," << t.chromatag.view_angle_deg << ","
      << t.apriltag.size_px << "," << t.apriltag.view_angle_deg << "," << DatasetKindName(t.kind)
      << "," << t.family << "," << t.quiet_zone_cells << "," << t.cast << "," << t.gradient << ","
      << t.tone_gamma << "," << t.print_chroma << "," << t.shot_snr << "," << t.read_noise << ","
      << BayerModeName(t.bayer) << "," << PrintKindName(t.print) << "," << t.red_gain << ","
      << t.blue_gain << "," << t.mixed_light;
}

// What each detector, ChromaTag alone and the calibrated configs found, and
// ChromaTag's stages and miss.
void WriteDetectionColumns(std::ostream& out, const FrameRecord& r) {
  for (const DetectorRecord& d : r.detectors) {
    double mean = 0;
    for (double e : d.score.corner_error_px) mean += e / 4;
    if (!d.ran) {
      out << ",,,,,,";
      continue;
    }
    out << "," << d.time_us << "," << d.score.found << "," << d.score.false_positives << ","
        << d.score.duplicates << "," << (d.score.found ? std::to_string(mean) : "") << ","
        << (d.score.found ? std::to_string(d.score.mean_radial_offset_px) : "");
  }
  out << ",";
  if (!std::isnan(r.chromatag_alone_us)) out << r.chromatag_alone_us;
  out << ",";
  if (r.calibrated.ran) {
    out << r.calibrated.score.found << "," << r.calibrated.score.false_positives << ","
        << r.calibrated.score.duplicates;
  } else {
    out << ",,";
  }
  for (double us : r.chromatag_summary.stage_time_us) out << "," << us;
  for (int n : r.chromatag_summary.rejected) out << "," << n;
  out << "," << r.chromatag_summary.seeds << ",";
  if (r.chromatag_miss.analysed) {
    out << MissStageName(r.chromatag_miss.stage) << ",\"" << r.chromatag_miss.reason << "\"";
  } else {
    out << ",";
  }
}

// Each detector's pose errors; empty where no pose was measured.
void WritePoseColumns(std::ostream& out, const FrameRecord& r) {
  auto number = [&out](double v) {
    out << ",";
    if (!std::isnan(v)) out << v;
  };
  for (const DetectorRecord& d : r.detectors) {
    number(d.rotation_error_deg);
    number(d.translation_error_pct);
  }
  number(r.chromatag_four_corner_rotation_error_deg);
  number(r.chromatag_four_corner_translation_error_pct);
  for (double z : r.detectors[kChromaTag].pose_z) number(z);
  number(r.detectors[kChromaTag].pose_nees);
}

bool WriteCsv(const Context& c) {
  std::ofstream out(c.out_dir + "/frames.csv");
  WriteCsvHeader(out);
  for (const auto& r : c.records) {
    WriteTruthColumns(out, r.truth);
    WriteDetectionColumns(out, r);
    WritePoseColumns(out, r);
    out << "\n";
  }
  out.close();
  if (!out) {
    if (c.error) *c.error = "cannot write " + c.out_dir + "/frames.csv";
    return false;
  }
  return true;
}

}  // namespace

bool WriteReport(const std::vector<FrameRecord>& records, const ReportInfo& info,
                 const std::string& out_dir, std::string* markdown, std::string* error) {
  Context c{records, info, out_dir, error};
  for (const auto& r : records) (r.truth.has_tags ? c.tagged : c.tag_free) += 1;
  std::string figures;
  if (!FigureSection(c, &figures) || !WriteCsv(c)) return false;
  std::ostringstream out;
  out << (info.label.empty() ? "" : "Measured: " + info.label + "  \n") << "Command: `"
      << info.command << "`  \n"
      << "CPU: " << info.cpu << "; " << info.load << "."
      << (info.build.empty() ? "" : " Build: " + info.build + ".")
      << " Detectors on one thread; rendering took " << Fixed(info.times.render_s, 0)
      << " s, the timed detection loop " << Fixed(info.times.detect_s, 0)
      << " s, explaining ChromaTag's misses (untimed) " << Fixed(info.times.analysis_s, 0)
      << " s.\n\n"
      << DatasetSection(c) << "\n";
  const std::string targets = TargetsSection(c);
  if (!targets.empty()) out << targets << "\n";
  out << FpsTable(c) << "\n"
      << StageTable(c) << "\n"
      << PrecisionRecallTable(c) << "\n"
      << FailureTable(c) << "\n"
      << figures << "\n"
      << FamilyRecallSection(c) << "\n"
      << PrintRecallSection(c) << "\n"
      << ConditionRecallSection(c) << "\n";
  const std::string casts = CastRecallSection(c);
  if (!casts.empty()) out << casts << "\n";
  out << CornerTable(c) << "\n"
      << PoseSection(c) << "\n"
      << PoseUncertaintySection(c) << "\n"
      << FalseDetectionTable(c);
  *markdown = out.str();
  std::ofstream file(out_dir + "/report.md");
  file << *markdown;
  file.close();
  if (!file) {
    if (error) *error = "cannot write " + out_dir + "/report.md";
    return false;
  }
  return true;
}

}  // namespace chromatag::bench
