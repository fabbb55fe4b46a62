#include "calib_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "report_util.h"

namespace chromatag::bench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

using Measure = double (*)(const CalibrationOutcome&);

// One row of the results: a number per trial and tool, smaller better.
struct Metric {
  const char* name;
  const char* unit;  // Appended to every value ("%", " px", "").
  int digits;
  double limit;  // The bound set for ChromaTag's value; NaN: none.
  Measure value;
  // The same in the tool's own pixel convention
  // (CalibrationOutcome::pixel_centre), where that changes it.
  Measure own = nullptr;
};

double Distortion(const CalibrationOutcome& o, size_t i) {
  return i < o.camera.distortion.size() ? o.camera.distortion[i] : 0.0;
}

// Signed errors against the true camera; a failed calibration has none.
double FxError(const CalibrationOutcome& o) { return 100 * (o.camera.fx / TrueCamera().fx - 1); }
double FyError(const CalibrationOutcome& o) { return 100 * (o.camera.fy / TrueCamera().fy - 1); }
double CxError(const CalibrationOutcome& o) { return o.camera.cx - TrueCamera().cx; }
double CyError(const CalibrationOutcome& o) { return o.camera.cy - TrueCamera().cy; }
double OwnCxError(const CalibrationOutcome& o) { return CxError(o) - o.pixel_centre; }
double OwnCyError(const CalibrationOutcome& o) { return CyError(o) - o.pixel_centre; }
double K1Error(const CalibrationOutcome& o) {
  return Distortion(o, 0) - TrueCamera().distortion[0];
}
double K2Error(const CalibrationOutcome& o) {
  return Distortion(o, 1) - TrueCamera().distortion[1];
}

template <double (*Signed)(const CalibrationOutcome&)>
double Abs(const CalibrationOutcome& o) {
  return o.ok ? std::abs(Signed(o)) : kInf;
}

double Rms(const CalibrationOutcome& o) { return o.ok ? o.rms_px : kInf; }

// The limits set for ChromaTag: fx and fy within 0.1 %, each coordinate of the
// principal point within 1 px, k1 within 0.005, rms at most 0.2 px.
const Metric kLimited[] = {
    {"fx error", " %", 3, 0.1, Abs<FxError>},
    {"fy error", " %", 3, 0.1, Abs<FyError>},
    {"cx error", " px", 2, 1.0, Abs<CxError>, Abs<OwnCxError>},
    {"cy error", " px", 2, 1.0, Abs<CyError>, Abs<OwnCyError>},
    {"k1 error", "", 4, 0.005, Abs<K1Error>},
    {"k2 error", "", 4, std::nan(""), Abs<K2Error>},
    {"reprojection rms", " px", 3, 0.2, Rms},
};

std::string Fixed(double value, int digits, const char* unit = "") {
  if (std::isinf(value)) return "failed";
  if (std::isnan(value)) return "–";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f%s", digits, value, unit);
  return text;
}

std::string Signed(double value, int digits) {
  if (std::abs(value) < 0.5 * std::pow(10.0, -digits)) value = 0;  // Not "-0.0000".
  char text[64];
  std::snprintf(text, sizeof text, "%+.*f", digits, value);
  return text;
}

std::vector<double> Values(const std::vector<TrialResult>& trials, int tool, Measure value) {
  std::vector<double> out;
  for (const TrialResult& t : trials) out.push_back(value(t.outcome[tool]));
  return out;
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t half = v.size() / 2;
  return v.size() % 2 ? v[half] : 0.5 * (v[half - 1] + v[half]);
}

double Worst(const std::vector<double>& v) {
  return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end());
}

// "better (0.52x)" when ChromaTag's median is below ChArUco's.
std::string AgainstCharuco(double chromatag, double charuco) {
  if (std::isinf(chromatag) || std::isinf(charuco)) {
    return std::isinf(chromatag) == std::isinf(charuco) ? "–"
           : std::isinf(chromatag)                      ? "**worse**"
                                                        : "better";
  }
  const char* word = chromatag < charuco ? "better" : chromatag > charuco ? "**worse**" : "equal";
  if (charuco <= 0) return word;
  char text[64];
  std::snprintf(text, sizeof text, "%s (%.2f×)", word, chromatag / charuco);
  return text;
}

std::string WithinLimit(const std::vector<double>& values, double limit) {
  if (std::isnan(limit)) return "(no limit)";
  const long within =
      std::count_if(values.begin(), values.end(), [&](double v) { return v <= limit; });
  const bool all = within == static_cast<long>(values.size());
  return (all ? "pass (" : "**fail** (") + std::to_string(within) + " of " +
         std::to_string(values.size()) + ")";
}

// "0.64 px", or "0.64 px (0.14)" when the tool's own convention gives
// another value.
std::string WithOwn(double value, double own, const Metric& m) {
  const std::string text = Fixed(value, m.digits, m.unit);
  const std::string own_text = Fixed(own, m.digits);
  return m.own && own_text != Fixed(value, m.digits) ? text + " (" + own_text + ")" : text;
}

std::string LimitsTable(const std::vector<TrialResult>& trials) {
  std::vector<std::vector<std::string>> rows;
  for (const Metric& m : kLimited) {
    const Measure own = m.own ? m.own : m.value;
    std::vector<std::string> row = {
        m.name, std::isnan(m.limit) ? "–" : "≤ " + Fixed(m.limit, m.digits, m.unit)};
    std::array<double, kNumCalibrationTools> medians{};
    for (int tool = 0; tool < kNumCalibrationTools; ++tool) {
      const auto values = Values(trials, tool, m.value);
      const auto owns = Values(trials, tool, own);
      medians[tool] = Median(values);
      row.push_back(WithOwn(Median(values), Median(owns), m));
      row.push_back(WithOwn(Worst(values), Worst(owns), m));
      if (tool == kChromaTagBoard) row.push_back(WithinLimit(values, m.limit));
    }
    row.push_back(AgainstCharuco(medians[kChromaTagBoard], medians[kCharucoBoard]));
    rows.push_back(row);
  }
  return Markdown({"", "limit (ChromaTag)", "ChromaTag median", "ChromaTag worst",
                   "ChromaTag trials within the limit", "ChArUco median", "ChArUco worst",
                   "ChromaTag's median against ChArUco's"},
                  rows);
}

// Trials in which a tool met every limit.
int TrialsWithinAllLimits(const std::vector<TrialResult>& trials, int tool) {
  int count = 0;
  for (const TrialResult& t : trials) {
    bool all = true;
    for (const Metric& m : kLimited)
      all &= std::isnan(m.limit) || m.value(t.outcome[tool]) <= m.limit;
    count += all;
  }
  return count;
}

std::string OtherTable(const std::vector<TrialResult>& trials) {
  const Metric kRows[] = {
      {"corner error against the truth, median px (corners found)", "", 3, std::nan(""),
       [](const CalibrationOutcome& o) { return o.corner_error_px; },
       [](const CalibrationOutcome& o) { return o.corner_error_own_px; }},
      {"views used", "", 0, std::nan(""),
       [](const CalibrationOutcome& o) { return double(o.views_used); }},
      {"corners used", "", 0, std::nan(""),
       [](const CalibrationOutcome& o) { return double(o.corners_used); }},
      {"detection, ms per view", "", 2, std::nan(""),
       [](const CalibrationOutcome& o) { return o.detect_ms_per_view; }},
      {"calibration, ms", "", 1, std::nan(""),
       [](const CalibrationOutcome& o) { return o.calibrate_ms; }},
  };
  std::vector<std::vector<std::string>> rows;
  for (const Metric& m : kRows) {
    std::vector<std::string> row = {m.name};
    for (int tool = 0; tool < kNumCalibrationTools; ++tool) {
      const auto v = Values(trials, tool, m.value);
      const auto owns = Values(trials, tool, m.own ? m.own : m.value);
      const auto [low, high] = std::minmax_element(v.begin(), v.end());
      const auto [own_low, own_high] = std::minmax_element(owns.begin(), owns.end());
      row.push_back(WithOwn(Median(v), Median(owns), m));
      row.push_back(WithOwn(*low, *own_low, m) + "–" + WithOwn(*high, *own_high, m));
    }
    rows.push_back(row);
  }
  return Markdown({"", "ChromaTag median", "ChromaTag range", "ChArUco median", "ChArUco range"},
                  rows);
}

std::string TrialsTable(const std::vector<TrialResult>& trials) {
  std::vector<std::vector<std::string>> rows;
  for (size_t t = 0; t < trials.size(); ++t) {
    int out = 0, jpeg = 0;
    for (const ViewConditions& v : trials[t].views) {
      out += v.partly_out;
      jpeg += v.jpeg_quality > 0;
    }
    for (int tool = 0; tool < kNumCalibrationTools; ++tool) {
      const CalibrationOutcome& o = trials[t].outcome[tool];
      std::vector<std::string> row = {std::to_string(t + 1), std::to_string(out),
                                      std::to_string(jpeg), CalibrationToolName(tool)};
      if (o.ok) {
        const auto centre = [&](double value, double own) {
          return o.pixel_centre == 0 ? Signed(value, 2)
                                     : Signed(value, 2) + " (" + Signed(own, 2) + ")";
        };
        for (const std::string& cell :
             {Signed(FxError(o), 3), Signed(FyError(o), 3), centre(CxError(o), OwnCxError(o)),
              centre(CyError(o), OwnCyError(o)), Signed(K1Error(o), 4), Signed(K2Error(o), 4),
              Fixed(o.rms_px, 3)})
          row.push_back(cell);
      } else {
        row.push_back("failed: " + o.error);
        row.resize(row.size() + 6);
      }
      row.push_back(std::to_string(o.views_used));
      row.push_back(std::to_string(o.corners_used));
      rows.push_back(row);
    }
  }
  return Markdown({"trial", "views partly out", "JPEG views", "board", "fx %", "fy %", "cx px",
                   "cy px", "k1", "k2", "rms px", "views used", "corners used"},
                  rows);
}

std::string Header(const std::vector<TrialResult>& trials, const CalibrationRunInfo& info) {
  const CameraIntrinsics c = TrueCamera();
  std::ostringstream out;
  out << "Measured: " << (info.label.empty() ? "(no label)" : info.label) << "  \n"
      << "Command: `" << info.command << "`  \n"
      << "CPU: " << info.cpu << "; " << info.load << ". Build: " << info.build
      << ". Detection and calibration timed on one thread; rendering took "
      << Fixed(info.render_s, 0) << " s on " << info.options.render_threads
      << " thread(s), the whole run " << Fixed(info.total_s, 0) << " s.\n\n";
  out << "Both boards are photographed by the same simulated camera at the same poses, through "
         "the same blur, noise and JPEG, and each is found and fitted by its own tools. "
         "ChromaTag: the detector's defaults (no camera given), then `CalibrateCamera` with its "
         "defaults, which leaves out tags and views that fit badly. ChArUco: OpenCV 4.6 as its "
         "sample `calibrate_camera_charuco.cpp` does it, with the options a careful user turns "
         "on: `detectMarkers` with sub-pixel marker corners and `refineDetectedMarkers`; a "
         "first camera from the markers (`calibrateCameraAruco`); the chessboard corners "
         "interpolated with that camera and refined by `cornerSubPix` "
         "(`interpolateCornersCharuco`); then `calibrateCameraCharuco` on every view with at "
         "least 4 corners not all on one line. Both fit k1, k2, p1 and p2 (k3 fixed at 0), the "
         "camera's own model.\n\n";
  char camera[512];
  std::snprintf(camera, sizeof camera,
                "- Camera: %d x %d, fx %.0f, fy %.0f, cx %.0f, cy %.0f, pinhole with k1 %.2f, k2 "
                "%.2f, p1 %.4f, p2 %.4f; every pixel traced through the lens "
                "(`testing::PhotographPage`).\n",
                kImageWidth, kImageHeight, c.fx, c.fy, c.cx, c.cy, c.distortion[0], c.distortion[1],
                c.distortion[2], c.distortion[3]);
  out << camera << "- ChromaTag board: " << info.chromatag_board << ".\n"
      << "- ChArUco board: " << info.charuco_board << ".\n"
      << "- " << trials.size() << " trials of " << info.options.views << " views (seed "
      << info.options.seed
      << "): the board tilted 10–45° about an in-plane axis in any direction and turned up to "
         "15° in its plane, its width 30–80 % of the image's, its centre placed anywhere that "
         "keeps most of it in the frame (up to 15 % of it may leave the frame).\n"
      << "- Camera effects, the same for both boards in each view: Gaussian blur of σ 0–1 px "
         "in linear light (as a lens blurs), then Gaussian noise of σ 1 grey level on the 8-bit "
         "values, then JPEG of quality 80–95 in a third of the views (`testing::ApplyCamera`, "
         "not its linear-light sensor model).\n\n";
  return out.str();
}

std::string BoardPoseTable(const std::vector<TrialResult>& trials) {
  // ChromaTag's board poses over every trial's views.
  CovarianceTally c;
  for (const TrialResult& t : trials) {
    const CalibrationOutcome& o = t.outcome[kChromaTagBoard];
    for (size_t v = 0; v < o.board_pose_z.size(); ++v)
      c.Add(o.board_pose_z[v], o.board_pose_nees[v]);
  }
  std::ostringstream out;
  out << "| poses | x | y | z | rot x | rot y | rot z | in 95 % |\n"
      << "|---:|---:|---:|---:|---:|---:|---:|---:|\n"
      << "| " << c.poses();
  for (int axis = 0; axis < 6; ++axis) out << " | " << Fixed(c.Spread(axis), 2);
  out << " | " << Fixed(100 * c.Coverage(), 1) << " % |\n";
  return out.str();
}

nlohmann::json OutcomeJson(const CalibrationOutcome& o) {
  nlohmann::json j = {{"ok", o.ok},
                      {"views_used", o.views_used},
                      {"corners_used", o.corners_used},
                      {"detect_ms_per_view", o.detect_ms_per_view},
                      {"calibrate_ms", o.calibrate_ms},
                      {"corner_error_px", o.corner_error_px},
                      {"pixel_centre", o.pixel_centre},
                      {"corner_error_own_px", o.corner_error_own_px}};
  if (!o.board_pose_nees.empty()) {
    j["board_pose_z"] = o.board_pose_z;
    j["board_pose_nees"] = o.board_pose_nees;
  }
  if (!o.ok) {
    j["error"] = o.error;
    return j;
  }
  j["camera"] = {{"fx", o.camera.fx},
                 {"fy", o.camera.fy},
                 {"cx", o.camera.cx},
                 {"cy", o.camera.cy},
                 {"distortion", o.camera.distortion}};
  j["rms_px"] = o.rms_px;
  return j;
}

nlohmann::json ResultsJson(const std::vector<TrialResult>& trials, const CalibrationRunInfo& info) {
  const CameraIntrinsics c = TrueCamera();
  nlohmann::json out = {
      {"command", info.command},
      {"label", info.label},
      {"cpu", info.cpu},
      {"build", info.build},
      {"views_per_trial", info.options.views},
      {"seed", info.options.seed},
      {"true_camera",
       {{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}, {"distortion", c.distortion}}},
      {"image_size", {kImageWidth, kImageHeight}},
      {"chromatag_board", info.chromatag_board},
      {"charuco_board", info.charuco_board},
      {"trials", nlohmann::json::array()}};
  for (const TrialResult& t : trials) {
    nlohmann::json views = nlohmann::json::array();
    for (const ViewConditions& v : t.views) {
      views.push_back({{"tilt_deg", v.tilt_deg},
                       {"axis_deg", v.axis_deg},
                       {"spin_deg", v.spin_deg},
                       {"fill", v.fill},
                       {"blur_sigma_px", v.blur_sigma_px},
                       {"jpeg_quality", v.jpeg_quality},
                       {"partly_out", v.partly_out}});
    }
    out["trials"].push_back({{"views", views},
                             {"render_s", t.render_s},
                             {"chromatag", OutcomeJson(t.outcome[kChromaTagBoard])},
                             {"charuco", OutcomeJson(t.outcome[kCharucoBoard])}});
  }
  return out;
}

}  // namespace

bool WriteCalibrationReport(const std::vector<TrialResult>& trials, const CalibrationRunInfo& info,
                            const std::string& out_dir, std::string* markdown, std::string* error) {
  std::ostringstream md;
  md << "# Camera calibration: a ChromaTag board against OpenCV's ChArUco\n\n"
     << "<!-- Written by bench/calib_comparison (scripts/bench.sh --publish copies it here); "
        "do not edit. -->\n\n"
     << Header(trials, info);
  const int n = static_cast<int>(trials.size());
  md << "## Against the limits\n\n"
     << "Absolute errors against the true camera, the median and the worst of " << n
     << " trials. The limits, set for ChromaTag: fx and fy within 0.1 %, each "
        "coordinate of the principal point within 1 px, k1 within 0.005, reprojection rms at "
        "most 0.2 px. ChromaTag met every limit in "
     << TrialsWithinAllLimits(trials, kChromaTagBoard) << " of " << n << " trials, ChArUco in "
     << TrialsWithinAllLimits(trials, kCharucoBoard) << " of " << n
     << ". The last column divides ChromaTag's median by ChArUco's. The two rms values are "
        "over different corners (ChromaTag's twelve ring corners per tag, ChArUco's chessboard "
        "corners), each its own fit's.\n\n"
     << "OpenCV 4.6's `interpolateCornersCharuco` adds half a pixel in x and y to the corners "
        "its `cornerSubPix` finds, so ChArUco's corners, and with them its principal point, "
        "lie half a pixel right of and below where OpenCV's projection functions (and "
        "ChromaTag) put them (a known OpenCV bug, opencv/opencv#25539, fixed in releases after "
        "4.6). In brackets, ChArUco's values with that half pixel taken out; "
        "the comparison uses them as returned, as a program that undistorts with OpenCV "
        "would.\n\n"
     << LimitsTable(trials) << "\n";
  md << "## Corners and time\n\n"
     << "Over the " << n
     << " trials. The corner error compares every corner each detector "
        "reported on its board (before the fit leaves any out) with where the true camera puts "
        "it (in brackets for ChArUco: moved by its half pixel). Views and corners used: those "
        "the final fit used. Detection: ChromaTag's detector; for ChArUco, finding the markers "
        "and interpolating the corners. Calibration: `CalibrateCamera`; "
        "`calibrateCameraAruco` and `calibrateCameraCharuco`.\n\n"
     << OtherTable(trials) << "\n";
  md << "## Board pose uncertainty\n\n"
     << "ChromaTag's board pose (`EstimateBoardPose` with the true camera) in every view of "
        "every trial, against the true pose, in its covariance's terms (`BoardPose::covariance`, "
        "ROS order): per axis, translation x, y, z then the small rotation about the camera's "
        "axes that takes the estimate to the truth, the root mean square of the error over its "
        "predicted standard deviation (1 when the covariance is right), and the share of poses "
        "inside the covariance's 95 % ellipsoid (squared Mahalanobis distance within 12.59).\n\n"
     << BoardPoseTable(trials) << "\n";
  md << "## Every trial\n\n"
     << "Signed errors (estimate minus truth); ChArUco's principal point also without its "
        "half pixel, in brackets. Views partly out: views with a corner of the board outside "
        "the frame.\n\n"
     << TrialsTable(trials) << "\n"
     << "To reproduce: `cmake --build build --target calib_comparison && "
        "build/bench/calib_comparison --out DIR` (`scripts/bench.sh` runs it with the other "
        "benchmarks and `--publish` copies its report here).\n";
  *markdown = md.str();
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream file(out_dir + "/" + name);
    file << text;
    if (file) return true;
    *error = "cannot write " + out_dir + "/" + name;
    return false;
  };
  return write("report.md", *markdown) &&
         write("results.json", ResultsJson(trials, info).dump(2) + "\n");
}

}  // namespace chromatag::bench
