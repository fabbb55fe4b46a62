#include "chromatag/calib/camera_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"
#include "projection_check.h"

namespace chromatag {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A tag's ring corners (BoardTagCorners): the black square's four, then the
// green/black square's and the red/green one's.
constexpr int kRingCorners = 12;

// One view's corners: per board tag seen, its twelve corners on the board
// (z = 0) and in the image, as detected and as fitted: less the bend the
// lens gives the detected corners under the last fit (StraightenCorners).
struct ViewPoints {
  std::vector<int> detection;  // Index into the view's detections, per tag.
  std::vector<std::vector<cv::Point3d>> board;
  std::vector<std::vector<cv::Point2d>> detected;
  std::vector<std::vector<cv::Point2d>> image;

  void Erase(size_t tag) {
    detection.erase(detection.begin() + static_cast<std::ptrdiff_t>(tag));
    board.erase(board.begin() + static_cast<std::ptrdiff_t>(tag));
    detected.erase(detected.begin() + static_cast<std::ptrdiff_t>(tag));
    image.erase(image.begin() + static_cast<std::ptrdiff_t>(tag));
  }
};

std::vector<cv::Point2d> RingCorners(const Detection& d) {
  std::vector<cv::Point2d> points(d.corners.begin(), d.corners.end());
  points.insert(points.end(), d.green_corners.begin(), d.green_corners.end());
  points.insert(points.end(), d.red_corners.begin(), d.red_corners.end());
  return points;
}

// Two views whose board tags' corners all lie within this distance of each
// other (pixels, the largest over the tags both show) are one view taken
// twice: copies of one image, or frames of a camera that did not move. A
// copy adds no information to the fit but shrinks its standard deviations
// as if it did.
constexpr double kSameViewPx = 1.0;

// The largest distance between the corners of the tags `a` and `b` both
// show, when each shows every tag the other does; infinite otherwise.
double LargestCornerShift(const ViewPoints& a, const std::vector<Detection>& a_detections,
                          const ViewPoints& b, const std::vector<Detection>& b_detections) {
  if (a.detection.size() != b.detection.size()) return std::numeric_limits<double>::infinity();
  double largest = 0;
  for (size_t i = 0; i < a.detection.size(); ++i) {
    const Detection& da = a_detections[a.detection[i]];
    size_t j = 0;
    while (j < b.detection.size() && !(b_detections[b.detection[j]].id == da.id &&
                                       b_detections[b.detection[j]].family == da.family))
      ++j;
    if (j == b.detection.size()) return std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < a.detected[i].size(); ++k)
      largest = std::max(largest, cv::norm(a.detected[i][k] - b.detected[j][k]));
  }
  return largest;
}

template <typename T>
std::vector<T> Flatten(const std::vector<std::vector<T>>& parts) {
  std::vector<T> all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  return all;
}

template <typename From, typename To>
std::vector<To> Convert(const std::vector<From>& points) {
  std::vector<To> out;
  out.reserve(points.size());
  for (const From& p : points) out.push_back(To(p));
  return out;
}

std::string Format(const char* format, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c);
  return text;
}

// The result of one fit over the views in `used`.
struct Fit {
  CameraIntrinsics camera;
  std::vector<cv::Vec3d> rvecs, tvecs;  // Per entry of `used`.
  double rms_px = 0.0;
  // The intrinsics' covariance (internal::IntrinsicCovariance), computed
  // here for both models: OpenCV's fisheye calibration gives none, and its
  // pinhole calibration (4.6) divides by N - P.
  cv::Mat covariance;
};

// OpenCV's camera matrix, distortion and poses into *fit.
void StoreFit(const cv::Mat& k, cv::Mat d, std::vector<cv::Mat> rvecs, std::vector<cv::Mat> tvecs,
              Fit* fit) {
  fit->camera.fx = k.at<double>(0, 0);
  fit->camera.fy = k.at<double>(1, 1);
  fit->camera.cx = k.at<double>(0, 2);
  fit->camera.cy = k.at<double>(1, 2);
  d.convertTo(d, CV_64F);
  fit->camera.distortion.assign(d.ptr<double>(), d.ptr<double>() + std::min<size_t>(d.total(), 5));
  fit->rvecs.clear();
  fit->tvecs.clear();
  for (size_t i = 0; i < rvecs.size(); ++i) {
    rvecs[i].convertTo(rvecs[i], CV_64F);
    tvecs[i].convertTo(tvecs[i], CV_64F);
    fit->rvecs.emplace_back(rvecs[i].ptr<double>());
    fit->tvecs.emplace_back(tvecs[i].ptr<double>());
  }
}

// Whether every number of the fit is finite.
bool IsFinite(const Fit& fit) {
  std::vector<double> all = {fit.camera.fx, fit.camera.fy, fit.camera.cx, fit.camera.cy,
                             fit.rms_px};
  all.insert(all.end(), fit.camera.distortion.begin(), fit.camera.distortion.end());
  for (size_t i = 0; i < fit.rvecs.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      all.push_back(fit.rvecs[i][c]);
      all.push_back(fit.tvecs[i][c]);
    }
  }
  return std::all_of(all.begin(), all.end(), [](double x) { return std::isfinite(x); });
}

// With `deviations`, also the intrinsics' covariance, which only the last
// fit needs.
bool RunFit(const std::vector<ViewPoints>& points, const std::vector<size_t>& used,
            cv::Size image_size, const CameraCalibrationOptions& options, Fit* fit,
            std::string* error, bool deviations = false) {
  std::vector<std::vector<cv::Point3d>> object;
  std::vector<std::vector<cv::Point2d>> image;
  for (size_t v : used) {
    object.push_back(Flatten(points[v].board));
    image.push_back(Flatten(points[v].image));
  }
  cv::Mat k, d;
  std::vector<cv::Mat> rvecs, tvecs;
  fit->camera = CameraIntrinsics();
  fit->camera.model = options.model;
  try {
    if (options.model == LensModel::kFisheye) {
      const int flags = cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC | cv::fisheye::CALIB_FIX_SKEW;
      fit->rms_px = cv::fisheye::calibrate(
          object, image, image_size, k, d, rvecs, tvecs, flags,
          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
    } else {
      // OpenCV's calibrateCamera takes single-precision points.
      std::vector<std::vector<cv::Point3f>> object_f;
      std::vector<std::vector<cv::Point2f>> image_f;
      for (size_t i = 0; i < object.size(); ++i) {
        object_f.push_back(Convert<cv::Point3d, cv::Point3f>(object[i]));
        image_f.push_back(Convert<cv::Point2d, cv::Point2f>(image[i]));
      }
      fit->rms_px = cv::calibrateCamera(object_f, image_f, image_size, k, d, rvecs, tvecs,
                                        (options.fit_k3 ? 0 : cv::CALIB_FIX_K3) | cv::CALIB_USE_LU);
    }
  } catch (const cv::Exception& e) {
    *error = "the fit failed (" + e.err + ")";
    return false;
  }
  StoreFit(k, d, rvecs, tvecs, fit);
  // A fit that diverged: nothing of it is usable.
  if (!IsFinite(*fit)) {
    *error = "the fit did not converge";
    return false;
  }
  if (deviations) {
    fit->covariance = internal::IntrinsicCovariance(fit->camera, object, image, fit->rvecs,
                                                    fit->tvecs, options.fit_k3, kRingCorners);
  }
  return true;
}

// Per tag of a view, its corners' residuals (projected minus detected).
std::vector<std::vector<cv::Point2d>> Residuals(const ViewPoints& view, const Fit& fit, size_t u) {
  std::vector<std::vector<cv::Point2d>> out;
  for (size_t t = 0; t < view.board.size(); ++t) {
    const std::vector<cv::Point2d> projected =
        ProjectPoints(fit.camera, view.board[t], fit.rvecs[u], fit.tvecs[u]);
    std::vector<cv::Point2d>& r = out.emplace_back();
    for (size_t i = 0; i < projected.size(); ++i) r.push_back(projected[i] - view.image[t][i]);
  }
  return out;
}

double Rms(const std::vector<std::vector<cv::Point2d>>& residuals) {
  double sum = 0;
  size_t n = 0;
  for (const auto& tag : residuals) {
    for (const cv::Point2d& e : tag) sum += e.dot(e);
    n += tag.size();
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

// What the used views leave weakly constrained, as Kalibr and calib.io warn.
// A view counts as tilted from this angle between the board's normal and
// the optical axis. With fewer than kMinTiltedViews such views the fit's
// focal length rests on the distortion model: four views within a degree
// of facing the camera (camera_calibration_test) gave fx 710.16 +- 0.01 px
// for a camera of 600.
constexpr double kTiltedViewDeg = 20.0;
constexpr int kMinTiltedViews = 2;

// The used views tilted kTiltedViewDeg or more; *largest_tilt the largest
// tilt of any used view.
int TiltedViews(const CameraCalibration& c, double* largest_tilt) {
  int tilted = 0;
  *largest_tilt = 0;
  for (const CalibrationViewResult& v : c.views) {
    if (!v.used) continue;
    tilted += v.tilt_deg >= kTiltedViewDeg ? 1 : 0;
    *largest_tilt = std::max(*largest_tilt, v.tilt_deg);
  }
  return tilted;
}

std::vector<std::string> Warnings(const CameraCalibration& c) {
  std::vector<std::string> out;
  int used = 0;
  double largest_tilt = 0;
  const int tilted = TiltedViews(c, &largest_tilt);
  constexpr int kGrid = 4;
  bool cell[kGrid][kGrid] = {};
  double reach = 0;  // Furthest corner from the image centre, as a share of the half diagonal.
  const cv::Point2d centre(0.5 * c.image_size.width, 0.5 * c.image_size.height);
  const double half_diagonal = cv::norm(centre);
  for (const CalibrationViewResult& v : c.views) {
    if (!v.used) continue;
    ++used;
    for (const cv::Point2d& p : v.corners) {
      const int gx = std::clamp(static_cast<int>(p.x * kGrid / c.image_size.width), 0, kGrid - 1);
      const int gy = std::clamp(static_cast<int>(p.y * kGrid / c.image_size.height), 0, kGrid - 1);
      cell[gy][gx] = true;
      reach = std::max(reach, cv::norm(p - centre) / half_diagonal);
    }
  }
  if (used < 10) {
    out.push_back(std::to_string(used) +
                  " views used: 15 to 30 views, the board tilted and in every part of the "
                  "image, give a dependable calibration");
  }
  if (tilted < 3 && tilted >= kMinTiltedViews) {  // Fewer: a doubt (Doubts).
    out.push_back(Format(
        "the focal length and principal point are weakly constrained: %.0f view(s) tilted 20 "
        "degrees or more (the largest tilt is %.0f degrees); add views with the board tilted "
        "20-45 degrees about different axes",
        tilted, largest_tilt));
  }
  int covered = 0;
  for (const auto& row : cell)
    for (bool b : row) covered += b ? 1 : 0;
  if (covered < kGrid * kGrid - 2 || reach < 0.8) {
    out.push_back(Format(
        "the distortion is weakly constrained: corners fall in %.0f of the image's 16 cells (4 "
        "x 4) and reach %.0f %% of the way from its centre to its corners; add views with the "
        "board near the edges and corners of the image",
        covered, 100.0 * reach));
  }
  return out;
}

// The projection check's doubts (CameraCalibration::doubts): the
// uncertainty or the cross-validation over its limit, or no
// cross-validation.
void ProjectionDoubts(const ProjectionCheck& p, std::vector<std::string>* doubts) {
  std::vector<std::string>& out = *doubts;
  if (!(p.uncertainty_worst_px <= kMaxProjectionUncertaintyPx)) {
    out.push_back(
        Format(
            "the projection is uncertain: up to %.2f px (median %.2f) in the central 80 %% of the "
            "image at %.2f m",
            p.uncertainty_worst_px, p.uncertainty_median_px, p.distance) +
        Format(" (limit %.1f px); add views, tilted, covering the image",
               kMaxProjectionUncertaintyPx));
  }
  if (p.cross_validation_px.empty()) {
    out.push_back(
        "fewer than six views were used: the calibration cannot be checked against itself (two "
        "halves of the views fitted apart); add views");
  } else if (!(p.cross_validation_worst_px <= kMaxCrossValidationPx)) {
    const std::string apart =
        Format(
            "two halves of the views give models that project up to %.2f px apart (median %.2f) in "
            "the central 80 %% of the image at %.2f m",
            p.cross_validation_worst_px, p.cross_validation_median_px, p.distance) +
        Format(" (limit %.1f px)", kMaxCrossValidationPx);
    out.push_back(apart +
                  (p.cross_validation_beyond_noise
                       ? Format(", over %.0f times what the corners' noise explains: the views do "
                                "not agree on the lens; look for a view of a bent or moving board, "
                                "or try the other lens model",
                                kCrossValidationSigmas)
                       : std::string(", as the corners' noise gives so few views: add views")));
  }
}

// What the fit does not pin down (CameraCalibration::doubts): the focal
// length and principal point without tilted views, and the parameters
// whose standard deviations are over their limits.
std::vector<std::string> Doubts(const CameraCalibration& c, double distance_spread) {
  std::vector<std::string> out;
  double largest_tilt = 0;
  const int tilted = TiltedViews(c, &largest_tilt);
  if (tilted < kMinTiltedViews) {
    out.push_back(Format(
        "fx, fy, cx and cy are not pinned down: %.0f view(s) tilted 20 degrees or more (the "
        "largest tilt is %.0f degrees); a board facing the camera leaves the focal length to the "
        "lens's distortion, and the fit's deviations do not show it; add views with the board "
        "tilted 20-45 degrees about different axes",
        tilted, largest_tilt));
  }
  if (c.std_dev.size() >= 4) {
    const char* names[4] = {"fx", "fy", "cx", "cy"};
    const double values[4] = {c.camera.fx, c.camera.fy, c.camera.cx, c.camera.cy};
    for (int i = 0; i < 2; ++i) {
      if (c.std_dev[i] > 0.005 * values[i])
        out.push_back(
            std::string(names[i]) +
            Format(" is uncertain: %.1f +- %.1f px (more than 0.5 %%)", values[i], c.std_dev[i]));
    }
    for (int i = 2; i < 4; ++i) {
      const double side = i == 2 ? c.image_size.width : c.image_size.height;
      if (c.std_dev[i] > 0.01 * side)
        out.push_back(std::string(names[i]) +
                      Format(" is uncertain: %.1f +- %.1f px (more than 1 %% of the image)",
                             values[i], c.std_dev[i]));
    }
  }
  if (distance_spread < kMinDistanceSpread) {
    out.push_back(Format(
        "every view shows the board at about one distance (the furthest %.2f times the nearest, "
        "under %.1f): the focal length trades against the distance and the distortion is seen "
        "at one depth; add views with the board nearer and further",
        distance_spread, kMinDistanceSpread));
  }
  ProjectionDoubts(c.projection, &out);
  return out;
}

}  // namespace

bool CameraCalibrationOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (model == LensModel::kFisheye && fit_k3)
    return fail("k3 belongs to the pinhole model; the fisheye model always fits k1-k4");
  if (min_tags_per_view < 1) return fail("min_tags_per_view must be at least 1");
  if (!(max_view_rms_px > 0) || !(max_corner_error_px > 0) || !(corner_error_factor >= 1))
    return fail("max_view_rms_px and max_corner_error_px must be > 0 and corner_error_factor >= 1");
  return true;
}

bool CheckCalibrationBoard(const Board& board, const CameraCalibrationOptions& options,
                           std::string* error) {
  if (!board.IsValid(error)) return false;
  for (const BoardTag& tag : board.tags) {
    if (std::abs(tag.translation[2]) > 1e-9 || std::abs(tag.rotation(2, 2) - 1.0) > 1e-9) {
      if (error) *error = "camera calibration needs a planar board (every tag at z = 0, facing +z)";
      return false;
    }
  }
  if (static_cast<int>(board.tags.size()) < options.min_tags_per_view) {
    if (error)
      *error = "the board has " + std::to_string(board.tags.size()) + " tag(s); a view must show " +
               std::to_string(options.min_tags_per_view) + " or more of them";
    return false;
  }
  return true;
}

std::vector<std::string> CalibrationParameterNames(const CameraIntrinsics& camera) {
  std::vector<std::string> names = {"fx", "fy", "cx", "cy"};
  const std::vector<std::string> pinhole = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
  for (size_t i = 0; i < camera.distortion.size(); ++i)
    names.push_back(camera.model == LensModel::kFisheye ? "k" + std::to_string(i + 1) : pinhole[i]);
  return names;
}

namespace {

// What CalibrateCamera works on: each view's board corners, and the result
// that records what became of each view and tag.
struct Calibration {
  const Board& board;
  const std::vector<CalibrationView>& views;
  const CameraCalibrationOptions& options;
  CameraCalibration result;
  std::vector<ViewPoints> points;
  double distance_spread = 0.0;  // The used boards' furthest distance over the nearest.

  // Tag t of view v leaves the view, for `why`.
  void LeaveOut(size_t v, size_t t, const std::string& why) {
    result.views[v].tags_left_out.push_back(views[v].detections[points[v].detection[t]].id);
    result.views[v].why_left_out.push_back(why);
    points[v].Erase(t);
  }

  // Whether view v still shows enough board tags; if not, says so.
  bool Usable(size_t v) {
    if (static_cast<int>(points[v].board.size()) >= options.min_tags_per_view) return true;
    result.views[v].why_not = std::to_string(points[v].board.size()) +
                              " board tag(s) seen (needs " +
                              std::to_string(options.min_tags_per_view) + ")";
    return false;
  }
};

// Per view, the corners of its board tags on the board and in the image.
void CollectBoardCorners(Calibration* c) {
  const cv::Size image_size = c->result.image_size;
  c->points.resize(c->views.size());
  for (size_t v = 0; v < c->views.size(); ++v) {
    CalibrationViewResult& out = c->result.views.emplace_back();
    out.name = c->views[v].name;
    for (size_t i = 0; i < c->views[v].detections.size(); ++i) {
      const Detection& d = c->views[v].detections[i];
      if (d.family == nullptr) continue;
      const int index = c->board.Find(d.family->name(), d.id);
      if (index < 0) continue;
      // A tag cut by the image's edge has corners extrapolated from the
      // visible parts of its sides, straight where the lens bends them.
      const std::vector<cv::Point2d> corners = RingCorners(d);
      const bool inside = std::all_of(corners.begin(), corners.end(), [&](const cv::Point2d& p) {
        return p.x >= 0 && p.y >= 0 && p.x <= image_size.width - 1 && p.y <= image_size.height - 1;
      });
      if (!inside) {
        out.tags_left_out.push_back(d.id);
        out.why_left_out.push_back("a corner outside the image");
        continue;
      }
      c->points[v].detection.push_back(static_cast<int>(i));
      c->points[v].board.push_back(BoardTagCorners(c->board.tags[index], *d.family));
      c->points[v].detected.push_back(corners);
      c->points[v].image.push_back(corners);
    }
  }
}

// The views with enough board tags; a view taken twice is used once, the
// first time.
std::vector<size_t> UsableDistinctViews(Calibration* c) {
  std::vector<size_t> used;
  for (size_t v = 0; v < c->views.size(); ++v) {
    if (!c->Usable(v)) continue;
    bool repeat = false;
    for (size_t u : used) {
      const double shift = LargestCornerShift(c->points[v], c->views[v].detections, c->points[u],
                                              c->views[u].detections);
      if (shift <= kSameViewPx) {
        c->result.views[v].why_not = "the same view as '" + c->views[u].name +
                                     Format("' (every corner within %.2f px): used once", shift);
        repeat = true;
        break;
      }
    }
    if (!repeat) used.push_back(v);
  }
  return used;
}

// Fewer than three views left: what became of the others.
std::string TooFewViews(const Calibration& c) {
  int few_tags = 0, badly = 0, repeats = 0;
  for (const CalibrationViewResult& v : c.result.views) {
    few_tags += v.why_not.find("board tag") != std::string::npos ? 1 : 0;
    badly += v.why_not.find("reprojects") != std::string::npos ? 1 : 0;
    repeats += v.why_not.rfind("the same view as", 0) == 0 ? 1 : 0;
  }
  std::string message = "fewer than three views show enough of the board (" +
                        std::to_string(c.views.size()) + " given";
  if (few_tags)
    message += ", " + std::to_string(few_tags) + " with fewer than " +
               std::to_string(c.options.min_tags_per_view) + " of its tags";
  if (repeats)
    message += ", " + std::to_string(repeats) +
               " the same as another view (copies of one "
               "image, or a camera that did not move)";
  if (badly)
    message += Format(
        ", %.0f reprojecting worse than %.2f px rms: is the board file the board "
        "in the views?",
        badly, c.options.max_view_rms_px);
  return message + ")";
}

// The corners the next fit takes: each detected corner less the bend
// (CornerBend) the lens gives it under `fit`, for the views of
// `used` (fit's order).
void StraightenCorners(Calibration* c, const Fit& fit, const std::vector<size_t>& used) {
  for (size_t u = 0; u < used.size(); ++u) {
    ViewPoints& view = c->points[used[u]];
    for (size_t t = 0; t < view.board.size(); ++t) {
      const std::vector<cv::Point2d> bend =
          CornerBend(fit.camera, view.board[t], fit.rvecs[u], fit.tvecs[u]);
      for (size_t i = 0; i < bend.size(); ++i) view.image[t][i] = view.detected[t][i] - bend[i];
    }
  }
}

// Tags whose corners disagree with the others in their view under the
// first fit's camera (EstimateBoardPose's robust pose: a misread ID pulls
// the fitted view, not this) leave the view. Returns the views still usable.
std::vector<size_t> DropTagsOffBoardPose(Calibration* c, const std::vector<size_t>& used,
                                         const Fit& fit) {
  std::vector<size_t> kept;
  for (size_t v : used) {
    BoardPose pose;
    if (EstimateBoardPose(c->views[v].detections, c->board, fit.camera, &pose)) {
      for (size_t t = c->points[v].board.size(); t-- > 0;) {
        const auto& rejected = pose.detections_rejected;
        if (std::find(rejected.begin(), rejected.end(), c->points[v].detection[t]) !=
            rejected.end())
          c->LeaveOut(v, t, "disagrees with the other tags' board pose");
      }
    }
    if (c->Usable(v)) kept.push_back(v);
  }
  return kept;
}

// Views that fit badly leave the calibration and tags with a corner far from
// the fit leave their view. False when nothing changed.
bool DropPoorFits(Calibration* c, const Fit& fit, std::vector<size_t>* used) {
  const CameraCalibrationOptions& options = c->options;
  const double corner_limit =
      std::max(options.max_corner_error_px, options.corner_error_factor * fit.rms_px);
  bool changed = false;
  std::vector<size_t> kept;
  for (size_t u = 0; u < used->size(); ++u) {
    const size_t v = (*used)[u];
    const auto residuals = Residuals(c->points[v], fit, u);
    const double rms = Rms(residuals);
    if (rms > options.max_view_rms_px) {
      c->result.views[v].why_not =
          Format("reprojects at %.2f px rms (limit %.2f)", rms, options.max_view_rms_px);
      changed = true;
      continue;
    }
    for (size_t t = residuals.size(); t-- > 0;) {
      double worst = 0;
      for (const cv::Point2d& e : residuals[t]) worst = std::max(worst, cv::norm(e));
      if (worst > corner_limit) {
        c->LeaveOut(v, t,
                    Format("a corner %.2f px from the fit (limit %.2f)", worst, corner_limit));
        changed = true;
      }
    }
    if (c->Usable(v)) kept.push_back(v);
  }
  *used = kept;
  return changed;
}

// The final fit's camera, and per used view its corners, residuals, pose and
// tilt.
void RecordFit(const Fit& fit, const std::vector<size_t>& used, Calibration* c) {
  CameraCalibration& result = c->result;
  for (size_t u = 0; u < used.size(); ++u) {
    const size_t v = used[u];
    CalibrationViewResult& out = result.views[v];
    out.used = true;
    out.tags = static_cast<int>(c->points[v].board.size());
    const auto residuals = Residuals(c->points[v], fit, u);
    out.rms_px = Rms(residuals);
    out.corners = Flatten(c->points[v].detected);
    out.residuals = Flatten(residuals);
    out.rvec = fit.rvecs[u];
    out.tvec = fit.tvecs[u];
    cv::Matx33d r;
    cv::Rodrigues(out.rvec, r);
    out.tilt_deg = std::acos(std::min(1.0, std::abs(r(2, 2)))) * 180.0 / kPi;
    result.corners_used += static_cast<int>(out.corners.size());
  }
  result.camera = fit.camera;
  result.rms_px = fit.rms_px;
  // k3 held at 0 has no deviation.
  result.std_dev.clear();
  for (int i = 0; i < fit.covariance.rows; ++i)
    result.std_dev.push_back(std::sqrt(std::max(0.0, fit.covariance.at<double>(i, i))));
  result.std_dev.resize(4 + result.camera.distortion.size(), 0.0);
}

// The median distance of the used views' boards from the camera, metres
// (each board's used corners' centroid); *spread the furthest over the
// nearest.
double MedianBoardDistance(const Calibration& c, const Fit& fit, const std::vector<size_t>& used,
                           double* spread) {
  std::vector<double> distances;
  for (size_t u = 0; u < used.size(); ++u) {
    cv::Vec3d centre(0, 0, 0);
    const std::vector<cv::Point3d> board = Flatten(c.points[used[u]].board);
    for (const cv::Point3d& p : board) centre += cv::Vec3d(p.x, p.y, p.z) / double(board.size());
    cv::Matx33d r;
    cv::Rodrigues(fit.rvecs[u], r);
    distances.push_back(cv::norm(r * centre + fit.tvecs[u]));
  }
  std::sort(distances.begin(), distances.end());
  *spread = distances.front() > 0 ? distances.back() / distances.front() : 0.0;
  return distances[distances.size() / 2];
}

// CameraCalibration::projection: the final fit's projection uncertainty,
// and the models of two halves of the used views against each other.
void CheckProjection(Calibration& c, const Fit& fit, const std::vector<size_t>& used) {
  ProjectionCheck& check = c.result.projection;
  double spread = 0;
  const double median = MedianBoardDistance(c, fit, used, &spread);
  c.distance_spread = spread;
  check.distance = c.options.working_distance > 0 ? c.options.working_distance : median;
  const cv::Size size = c.result.image_size;
  check.grid =
      cv::Size(internal::kProjectionGrid,
               std::max(1, static_cast<int>(std::lround(internal::kProjectionGrid *
                                                        double(size.height) / size.width))));
  check.uncertainty_px = internal::UncertaintyMap(fit.camera, fit.covariance, c.options.fit_k3,
                                                  check.distance, size, check.grid);
  internal::CentralFigures(check.uncertainty_px, size, check.grid, &check.uncertainty_median_px,
                           &check.uncertainty_worst_px);
  check.cross_validation_median_px = check.cross_validation_worst_px =
      std::numeric_limits<double>::quiet_NaN();
  std::vector<size_t> halves[2];
  for (size_t u = 0; u < used.size(); ++u) halves[u % 2].push_back(used[u]);
  if (halves[1].size() < 3) return;
  Fit fits[2];
  std::vector<double> own[2];
  std::string why;
  for (int h = 0; h < 2; ++h) {
    if (!RunFit(c.points, halves[h], size, c.options, &fits[h], &why, /*deviations=*/true)) return;
    own[h] = internal::UncertaintyMap(fits[h].camera, fits[h].covariance, c.options.fit_k3,
                                      check.distance, size, check.grid);
  }
  check.cross_validation_px = internal::CrossValidationMap(fits[0].camera, fits[1].camera,
                                                           check.distance, size, check.grid);
  internal::CentralFigures(check.cross_validation_px, size, check.grid,
                           &check.cross_validation_median_px, &check.cross_validation_worst_px);
  for (size_t i = 0; i < own[0].size() && i < own[1].size(); ++i)
    check.cross_validation_expected_px.push_back(std::hypot(own[0][i], own[1][i]));
  check.cross_validation_beyond_noise =
      internal::BeyondNoise(check.cross_validation_px, check.cross_validation_expected_px, size,
                            check.grid, kMaxCrossValidationPx, kCrossValidationSigmas);
}

}  // namespace

std::optional<CameraCalibration> CalibrateCamera(const Board& board,
                                                 const std::vector<CalibrationView>& views,
                                                 cv::Size image_size,
                                                 const CameraCalibrationOptions& options,
                                                 std::string* error) {
  const auto fail = [&](const std::string& message) -> std::optional<CameraCalibration> {
    if (error) *error = message;
    return std::nullopt;
  };
  if (!options.IsValid(error) || !CheckCalibrationBoard(board, options, error)) return std::nullopt;
  if (image_size.width <= 0 || image_size.height <= 0) return fail("the image size is empty");
  Calibration c{board, views, options, CameraCalibration(), {}, 0.0};
  c.result.image_size = image_size;
  CollectBoardCorners(&c);
  std::vector<size_t> used = UsableDistinctViews(&c);
  if (used.size() < 3) return fail(TooFewViews(c));
  Fit fit;
  std::string why;
  if (!RunFit(c.points, used, image_size, options, &fit, &why)) return fail(why);
  StraightenCorners(&c, fit, used);
  used = DropTagsOffBoardPose(&c, used, fit);
  // Then refits, each to the corners straightened by the one before, until
  // nothing changes.
  for (int round = 0; round < 5; ++round) {
    if (used.size() < 3) return fail(TooFewViews(c));
    if (!RunFit(c.points, used, image_size, options, &fit, &why)) return fail(why);
    const std::vector<size_t> fitted = used;
    const bool changed = DropPoorFits(&c, fit, &used);
    StraightenCorners(&c, fit, fitted);
    if (!changed) break;
  }
  if (used.size() < 3) return fail(TooFewViews(c));
  if (!RunFit(c.points, used, image_size, options, &fit, &why, /*deviations=*/true))
    return fail(why);
  RecordFit(fit, used, &c);
  CheckProjection(c, fit, used);
  c.result.warnings = Warnings(c.result);
  c.result.doubts = Doubts(c.result, c.distance_spread);
  return c.result;
}

}  // namespace chromatag
