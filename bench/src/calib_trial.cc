#include "calib_trial.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/bench/metrics.h"
#include "chromatag/calib/camera_calibration.h"
#include "chromatag/detector/camera.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/sheet_request.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/rig/board_file.h"
#include "page_view.h"

namespace chromatag::bench {
namespace {

// Both pages: 320 x 240 mm at 6 pixels per mm, finer than the renderer's
// twice-as-fine samples of the nearest view (about 5 per mm), with a whole
// number of page pixels in a tag's 5.5 mm cell, a 28 mm square and a
// marker's 2 mm cell. 10 per mm gave the same results and took half as long
// again.
constexpr double kPxPerMm = 6.0;
constexpr char kPage[] = "320x240mm";
// The ChromaTag board: 6 x 4 16h5 tags of 33 mm, the generator's spacing
// (the 2-cell quiet zone, 11 mm): a pattern of 253 x 165 mm.
constexpr char kChromaTagGrid[] = "6x4";
constexpr char kChromaTagSize[] = "33mm";
// The ChArUco board covering about the same area: 9 x 6 squares of 28 mm
// (252 x 168 mm). 27 markers: the 4x4 dictionary of 50 has the largest cells
// of those that hold them. Markers of 12 mm: on these views ChArUco
// calibrated best with the smallest markers it still reads. Its
// cornerSubPix window reaches a marker's corner when the marker nearly fills
// its square: over 5 trials its median fx error was 0.14 % with 21 mm
// markers, 0.13 % with 17, 0.10 % with 14 and 0.06 % with 12; with 10 mm
// markers it misread some and one trial's fx came out 30 % off.
constexpr int kSquaresX = 9, kSquaresY = 6;
constexpr double kSquareMm = 28.0, kMarkerMm = 12.0;
constexpr cv::aruco::PREDEFINED_DICTIONARY_NAME kDictionary = cv::aruco::DICT_4X4_50;
constexpr char kDictionaryName[] = "DICT_4X4_50";
// Fewer ChArUco corners than this, or all on one line, cannot seed
// calibrateCamera's homography: such views are not passed to it.
constexpr int kMinCharucoCorners = 4;

// Poses and camera effects (same for both boards).
constexpr double kMinTiltDeg = 10, kMaxTiltDeg = 45, kMaxSpinDeg = 15;
constexpr double kMinFill = 0.3, kMaxFill = 0.8;
// How far past the frame the board's centre may be placed, as a share of
// the board's size in the image: some views then lose part of the board.
constexpr double kOvershoot = 0.15;
constexpr double kNoiseSigma = 1.0;  // 8-bit grey levels.
constexpr double kMaxBlurSigma = 1.0;
constexpr double kJpegShare = 1.0 / 3;
constexpr int kMinJpegQuality = 80, kMaxJpegQuality = 95;

using Clock = std::chrono::steady_clock;

double Milliseconds(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  const size_t half = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + half, v.end());
  if (v.size() % 2) return v[half];
  return 0.5 * (v[half] + *std::max_element(v.begin(), v.begin() + half));
}

std::array<cv::Point3d, 4> Rectangle(double left, double bottom, double right, double top) {
  return {cv::Point3d(left, top, 0), cv::Point3d(right, top, 0), cv::Point3d(right, bottom, 0),
          cv::Point3d(left, bottom, 0)};
}

void SetCentre(PrintedBoard* printed) {
  printed->centre = cv::Vec3d(0, 0, 0);
  for (const cv::Point3d& p : printed->outline) printed->centre += 0.25 * cv::Vec3d(p);
  printed->width_mm = 1000 * (printed->outline[1].x - printed->outline[0].x);
  printed->height_mm = 1000 * (printed->outline[0].y - printed->outline[3].y);
}

// The sheet `chromatag generate --board 6x4 --size 33mm --page 320x240mm`
// writes, as a PNG, with the board its sidecar describes.
bool PrintChromaTagBoard(CalibrationSetup* setup, std::string* error) {
  SheetRequest request;
  request.board = kChromaTagGrid;
  request.size = kChromaTagSize;
  request.page = kPage;
  request.format = "png";
  request.dpi = kPxPerMm * 25.4;
  SheetOptions options;
  if (!ToSheetOptions(request, "board.png", &options, error)) return false;
  const auto files = RenderSheet(options, "board.png", error);
  if (!files) return false;
  const auto record = ParseSidecar(files->back().contents, "", error);
  if (!record) return false;
  auto board = BoardFromSheet(*record, error);
  if (!board) return false;
  setup->chromatag_board = *board;
  PrintedBoard& printed = setup->chromatag;
  const std::string& png = files->front().contents;
  printed.page.bgr = cv::imdecode(std::vector<uchar>(png.begin(), png.end()), cv::IMREAD_COLOR);
  printed.page.px_per_mm = kPxPerMm;
  printed.page.origin_mm = record->board_origin_mm;
  double left = 1e9, bottom = 1e9, right = -1e9, top = -1e9;
  for (const BoardTag& tag : board->tags) {
    for (const cv::Point3d& p : BoardTagCorners(tag, *record->family)) {
      left = std::min(left, p.x), right = std::max(right, p.x);
      bottom = std::min(bottom, p.y), top = std::max(top, p.y);
    }
  }
  printed.outline = Rectangle(left, bottom, right, top);
  SetCentre(&printed);
  char text[256];
  std::snprintf(text, sizeof text,
                "%s %s tags of %.0f mm, %.0f mm apart (`chromatag generate --board %s --size %s`), "
                "%.0f x %.0f mm: %zu corners",
                kChromaTagGrid, record->family->name().c_str(), record->tag_size_mm,
                record->board->spacing_mm, kChromaTagGrid, kChromaTagSize, printed.width_mm,
                printed.height_mm, 12 * board->tags.size());
  printed.description = text;
  return true;
}

// OpenCV's drawing of the ChArUco board, on a white page of the ChromaTag
// sheet's size, centred.
void PrintCharucoBoard(CalibrationSetup* setup) {
  setup->charuco_board = cv::aruco::CharucoBoard::create(
      kSquaresX, kSquaresY, static_cast<float>(kSquareMm / 1000),
      static_cast<float>(kMarkerMm / 1000), cv::aruco::getPredefinedDictionary(kDictionary));
  const cv::Size pattern_px(static_cast<int>(std::lround(kSquaresX * kSquareMm * kPxPerMm)),
                            static_cast<int>(std::lround(kSquaresY * kSquareMm * kPxPerMm)));
  cv::Mat pattern, pattern_bgr;
  setup->charuco_board->draw(pattern_px, pattern, 0, 1);
  cv::cvtColor(pattern, pattern_bgr, cv::COLOR_GRAY2BGR);
  PrintedBoard& printed = setup->charuco;
  const cv::Size page_px = setup->chromatag.page.bgr.size();
  printed.page.bgr = cv::Mat(page_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Point top_left((page_px.width - pattern_px.width) / 2,
                           (page_px.height - pattern_px.height) / 2);
  pattern_bgr.copyTo(printed.page.bgr(cv::Rect(top_left, pattern_px)));
  printed.page.px_per_mm = kPxPerMm;
  printed.page.origin_mm = {top_left.x / kPxPerMm, (top_left.y + pattern_px.height) / kPxPerMm};
  printed.outline = Rectangle(0, 0, kSquaresX * kSquareMm / 1000, kSquaresY * kSquareMm / 1000);
  SetCentre(&printed);
  char text[256];
  std::snprintf(text, sizeof text,
                "%d x %d squares of %.0f mm, markers %.0f mm from %s (OpenCV's "
                "`CharucoBoard::create` and `draw`), %.0f x %.0f mm: %d corners",
                kSquaresX, kSquaresY, kSquareMm, kMarkerMm, kDictionaryName, printed.width_mm,
                printed.height_mm, (kSquaresX - 1) * (kSquaresY - 1));
  printed.description = text;
}

// A ChArUco corner (OpenCV's board frame: origin at the top-left, y down the
// board, z into it) in the page frame (y up from the bottom-left).
cv::Point3d CharucoCornerOnPage(const CalibrationSetup& setup, int id) {
  const cv::Point3f& p = setup.charuco_board->chessboardCorners[id];
  return {p.x, kSquaresY * kSquareMm / 1000 - p.y, 0.0};
}

// One pose: camera_from_page for each board (each board's centre at the
// same place in the camera, the boards turned alike).
struct Pose {
  cv::Vec3d rvec;
  cv::Vec3d centre_in_camera;
  cv::Vec3d Translation(const PrintedBoard& board) const {
    cv::Matx33d r;
    cv::Rodrigues(rvec, r);
    return centre_in_camera - r * board.centre;
  }
};

struct PlannedView {
  ViewConditions conditions;
  Pose pose;
  testing::SceneOptions effects;
};

PlannedView PlanView(const CalibrationSetup& setup, std::mt19937* rng) {
  const CameraIntrinsics camera = TrueCamera();
  std::uniform_real_distribution<double> unit(0, 1), sign(-1, 1);
  PlannedView view;
  ViewConditions& c = view.conditions;
  c.tilt_deg = kMinTiltDeg + (kMaxTiltDeg - kMinTiltDeg) * unit(*rng);
  c.axis_deg = 360 * unit(*rng);
  c.spin_deg = kMaxSpinDeg * sign(*rng);
  c.fill = kMinFill + (kMaxFill - kMinFill) * unit(*rng);
  c.blur_sigma_px = kMaxBlurSigma * unit(*rng);
  const bool jpeg = unit(*rng) < kJpegShare;
  const int quality = std::uniform_int_distribution<int>(kMinJpegQuality, kMaxJpegQuality)(*rng);
  c.jpeg_quality = jpeg ? quality : 0;
  // Where the centre goes: anywhere that keeps most of the board in view.
  const PrintedBoard& board = setup.chromatag;
  const double width_px = c.fill * kImageWidth;
  const double height_px = width_px * board.height_mm / board.width_mm;
  const double reach_x = std::max(0.0, (kImageWidth - width_px) / 2) + kOvershoot * width_px;
  const double reach_y = std::max(0.0, (kImageHeight - height_px) / 2) + kOvershoot * height_px;
  const double u = camera.cx + reach_x * sign(*rng);
  const double v = camera.cy + reach_y * sign(*rng);
  const double depth = camera.fx * board.width_mm / 1000 / width_px;
  view.pose.rvec = testing::BoardFacing(c.tilt_deg, c.axis_deg, c.spin_deg);
  view.pose.centre_in_camera = {(u - camera.cx) / camera.fx * depth,
                                (v - camera.cy) / camera.fy * depth, depth};
  const std::vector<cv::Point3d> outline(board.outline.begin(), board.outline.end());
  for (const cv::Point2d& p :
       ProjectPoints(camera, outline, view.pose.rvec, view.pose.Translation(board))) {
    c.partly_out |= p.x < -0.5 || p.y < -0.5 || p.x > kImageWidth - 0.5 || p.y > kImageHeight - 0.5;
  }
  view.effects.blur_sigma = c.blur_sigma_px;
  view.effects.blur_in_linear_light = true;
  view.effects.noise_sigma = kNoiseSigma;
  view.effects.jpeg_quality = c.jpeg_quality;
  view.effects.seed = static_cast<unsigned>((*rng)());
  return view;
}

// frames[2 * v + tool]: view v of each board, rendered on `threads` threads.
std::vector<cv::Mat> Render(const CalibrationSetup& setup, const std::vector<PlannedView>& views,
                            int threads) {
  std::vector<cv::Mat> frames(2 * views.size());
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t j; (j = next++) < frames.size();) {
      const PlannedView& view = views[j / 2];
      const PrintedBoard& board = j % 2 == kChromaTagBoard ? setup.chromatag : setup.charuco;
      frames[j] =
          testing::PhotographPage(board.page, TrueCamera(), cv::Size(kImageWidth, kImageHeight),
                                  view.pose.rvec, view.pose.Translation(board), view.effects);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  return frames;
}

std::vector<cv::Point2d> RingCorners(const Detection& d) {
  std::vector<cv::Point2d> points(d.corners.begin(), d.corners.end());
  points.insert(points.end(), d.green_corners.begin(), d.green_corners.end());
  points.insert(points.end(), d.red_corners.begin(), d.red_corners.end());
  return points;
}

// Each corner's distance from the truth, the truth moved by `pixel_centre`
// in x and y.
void AddDistances(const std::vector<cv::Point2d>& found, const std::vector<cv::Point2d>& truth,
                  double pixel_centre, std::vector<double>* distances) {
  const cv::Point2d shift(pixel_centre, pixel_centre);
  for (size_t i = 0; i < found.size(); ++i)
    distances->push_back(cv::norm(found[i] - truth[i] - shift));
}

// The board's pose from `detections` (the true camera given) against the
// truth (rvec, tvec), into out->board_pose_z and board_pose_nees.
void AddBoardPoseCheck(const CalibrationSetup& setup, const std::vector<Detection>& detections,
                       const cv::Vec3d& rvec, const cv::Vec3d& tvec, CalibrationOutcome* out) {
  BoardPose pose;
  if (!EstimateBoardPose(detections, setup.chromatag_board, TrueCamera(), &pose)) return;
  cv::Matx33d rotation, true_rotation;
  cv::Rodrigues(pose.rvec, rotation);
  cv::Rodrigues(rvec, true_rotation);
  std::array<double, 6> z;
  double nees = 0;
  if (PoseNormalisedError(rotation, pose.tvec, pose.covariance, true_rotation, tvec, &z, &nees)) {
    out->board_pose_z.push_back(z);
    out->board_pose_nees.push_back(nees);
  }
}

CalibrationOutcome CalibrateWithChromaTag(const CalibrationSetup& setup,
                                          const std::vector<PlannedView>& plan,
                                          const std::vector<cv::Mat>& frames) {
  CalibrationOutcome out;
  std::vector<CalibrationView> views;
  std::vector<double> distances;
  double detect_ms = 0;
  for (size_t v = 0; v < plan.size(); ++v) {
    const auto start = Clock::now();
    DetectionResult result =
        setup.chromatag_detector->Detect(frames[2 * v + kChromaTagBoard], PixelOrder::kBgr);
    detect_ms += Milliseconds(start);
    const cv::Vec3d tvec = plan[v].pose.Translation(setup.chromatag);
    for (const Detection& d : result.detections) {
      const int index = d.family ? setup.chromatag_board.Find(d.family->name(), d.id) : -1;
      if (index < 0) continue;
      const std::vector<cv::Point3d> corners =
          BoardTagCorners(setup.chromatag_board.tags[index], *d.family);
      AddDistances(RingCorners(d), ProjectPoints(TrueCamera(), corners, plan[v].pose.rvec, tvec),
                   0.0, &distances);
    }
    AddBoardPoseCheck(setup, result.detections, plan[v].pose.rvec, tvec, &out);
    views.push_back({"view " + std::to_string(v + 1), std::move(result.detections)});
  }
  out.detect_ms_per_view = detect_ms / static_cast<double>(plan.size());
  out.corner_error_px = out.corner_error_own_px = Median(distances);
  const auto start = Clock::now();
  const auto calibration =
      CalibrateCamera(setup.chromatag_board, views, {kImageWidth, kImageHeight}, {}, &out.error);
  out.calibrate_ms = Milliseconds(start);
  if (!calibration) return out;
  out.ok = true;
  out.camera = calibration->camera;
  out.rms_px = calibration->rms_px;
  out.corners_used = calibration->corners_used;
  for (const CalibrationViewResult& view : calibration->views) out.views_used += view.used;
  return out;
}

// One view's ArUco markers on the ChArUco board.
struct MarkerView {
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
};

// Markers with sub-pixel corners, then missed markers looked for again
// where the board puts them (refineDetectedMarkers, given the same
// parameters so that the markers it recovers are refined too).
MarkerView DetectMarkers(const CalibrationSetup& setup, const cv::Mat& grey) {
  MarkerView view;
  std::vector<std::vector<cv::Point2f>> rejected;
  const cv::Ptr<cv::aruco::Board> board = setup.charuco_board;
  cv::aruco::detectMarkers(grey, board->dictionary, view.corners, view.ids,
                           setup.charuco_parameters, rejected);
  cv::aruco::refineDetectedMarkers(grey, board, view.corners, view.ids, rejected, cv::noArray(),
                                   cv::noArray(), 10.f, 3.f, true, cv::noArray(),
                                   setup.charuco_parameters);
  return view;
}

// calibrateCameraAruco on every view's marker corners: the first camera,
// from which interpolateCornersCharuco predicts where each chessboard
// corner lies before its cornerSubPix.
bool CameraFromMarkers(const CalibrationSetup& setup, const std::vector<MarkerView>& views,
                       cv::Mat* k, cv::Mat* d, std::string* error) {
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids, counts;
  for (const MarkerView& view : views) {
    if (view.ids.empty()) continue;
    corners.insert(corners.end(), view.corners.begin(), view.corners.end());
    ids.insert(ids.end(), view.ids.begin(), view.ids.end());
    counts.push_back(static_cast<int>(view.ids.size()));
  }
  try {
    cv::aruco::calibrateCameraAruco(corners, ids, counts, setup.charuco_board,
                                    {kImageWidth, kImageHeight}, *k, *d, cv::noArray(),
                                    cv::noArray(), cv::CALIB_FIX_K3);
  } catch (const cv::Exception& e) {
    *error = "calibrateCameraAruco failed (" + e.err + ")";
    return false;
  }
  return true;
}

// calibrateCameraCharuco's input: per view, chessboard corners and their IDs.
struct CharucoViews {
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<std::vector<int>> ids;
};

// Every view's chessboard corners, interpolated with the first camera (k,
// d) and refined by interpolateCornersCharuco's cornerSubPix; those of the
// views the fit can use are kept. Adds the time to *detect_ms and sets
// out's corner errors, views and corners used.

CharucoViews InterpolateCorners(const CalibrationSetup& setup, const std::vector<PlannedView>& plan,
                                const std::vector<MarkerView>& markers,
                                const std::vector<cv::Mat>& greys, const cv::Mat& k,
                                const cv::Mat& d, double* detect_ms, CalibrationOutcome* out) {
  CharucoViews kept;
  std::vector<double> distances, own_distances;
  for (size_t v = 0; v < plan.size(); ++v) {
    std::vector<cv::Point2f> corners;
    std::vector<int> ids;
    const auto start = Clock::now();
    if (!markers[v].ids.empty()) {
      cv::aruco::interpolateCornersCharuco(markers[v].corners, markers[v].ids, greys[v],
                                           setup.charuco_board, corners, ids, k, d);
    }
    *detect_ms += Milliseconds(start);
    std::vector<cv::Point3d> board_points;
    for (int id : ids) board_points.push_back(CharucoCornerOnPage(setup, id));
    const std::vector<cv::Point2d> found(corners.begin(), corners.end());
    const std::vector<cv::Point2d> truth = ProjectPoints(
        TrueCamera(), board_points, plan[v].pose.rvec, plan[v].pose.Translation(setup.charuco));
    AddDistances(found, truth, 0.0, &distances);
    AddDistances(found, truth, out->pixel_centre, &own_distances);
    if (static_cast<int>(ids.size()) < kMinCharucoCorners ||
        cv::aruco::testCharucoCornersCollinear(setup.charuco_board, ids))
      continue;
    out->corners_used += static_cast<int>(ids.size());
    kept.corners.push_back(std::move(corners));
    kept.ids.push_back(std::move(ids));
  }
  out->corner_error_px = Median(distances);
  out->corner_error_own_px = Median(own_distances);
  out->views_used = static_cast<int>(kept.ids.size());
  return kept;
}

// OpenCV 4.6's ChArUco calibration as its sample
// (modules/aruco/samples/calibrate_camera_charuco.cpp) does it, with the
// options a careful user turns on: markers found with sub-pixel corners and
// refineDetectedMarkers in every view; a first camera from the markers
// (calibrateCameraAruco); the chessboard corners interpolated with that
// camera and refined by cornerSubPix (interpolateCornersCharuco); then
// calibrateCameraCharuco. Detection time counts both passes over the images,
// calibration time both fits.
CalibrationOutcome CalibrateWithCharuco(const CalibrationSetup& setup,
                                        const std::vector<PlannedView>& plan,
                                        const std::vector<cv::Mat>& frames) {
  CalibrationOutcome out;
  out.pixel_centre = 0.5;
  std::vector<cv::Mat> greys(plan.size());
  std::vector<MarkerView> markers(plan.size());
  auto start = Clock::now();
  for (size_t v = 0; v < plan.size(); ++v) {
    cv::cvtColor(frames[2 * v + kCharucoBoard], greys[v], cv::COLOR_BGR2GRAY);
    markers[v] = DetectMarkers(setup, greys[v]);
  }
  double detect_ms = Milliseconds(start);
  start = Clock::now();
  cv::Mat k, d;
  const bool first_camera = CameraFromMarkers(setup, markers, &k, &d, &out.error);
  out.calibrate_ms = Milliseconds(start);
  if (!first_camera) return out;
  const CharucoViews views =
      InterpolateCorners(setup, plan, markers, greys, k, d, &detect_ms, &out);
  out.detect_ms_per_view = detect_ms / static_cast<double>(plan.size());
  if (views.ids.size() < 3) {
    out.error = "fewer than three views show enough of the board";
    return out;
  }
  start = Clock::now();
  try {
    // The model ChromaTag fits by default and the camera has: k1, k2, p1, p2.
    out.rms_px = cv::aruco::calibrateCameraCharuco(views.corners, views.ids, setup.charuco_board,
                                                   {kImageWidth, kImageHeight}, k, d, cv::noArray(),
                                                   cv::noArray(), cv::CALIB_FIX_K3);
  } catch (const cv::Exception& e) {
    out.error = "calibrateCameraCharuco failed (" + e.err + ")";
    return out;
  }
  out.calibrate_ms += Milliseconds(start);
  out.ok = true;
  out.camera.fx = k.at<double>(0, 0);
  out.camera.fy = k.at<double>(1, 1);
  out.camera.cx = k.at<double>(0, 2);
  out.camera.cy = k.at<double>(1, 2);
  d.convertTo(d, CV_64F);
  out.camera.distortion.assign(d.ptr<double>(), d.ptr<double>() + d.total());
  return out;
}

}  // namespace

CameraIntrinsics TrueCamera() { return testing::BarrelCamera(); }

const char* CalibrationToolName(int tool) {
  return tool == kChromaTagBoard ? "ChromaTag" : "ChArUco";
}

std::optional<CalibrationSetup> MakeCalibrationSetup(std::string* error) {
  CalibrationSetup setup;
  if (!PrintChromaTagBoard(&setup, error)) return std::nullopt;
  DetectorOptions options;  // The defaults; no camera: it is what is sought.
  options.families = {setup.chromatag_board.tags.front().family};
  setup.chromatag_detector = Detector::Create(options, error);
  if (!setup.chromatag_detector) return std::nullopt;
  PrintCharucoBoard(&setup);
  setup.charuco_parameters = cv::aruco::DetectorParameters::create();
  setup.charuco_parameters->cornerRefinementMethod = cv::aruco::CORNER_REFINE_SUBPIX;
  return setup;
}

TrialResult RunCalibrationTrial(const CalibrationSetup& setup, const TrialOptions& options,
                                int trial) {
  std::seed_seq seeds{options.seed, static_cast<unsigned>(trial)};
  std::mt19937 rng(seeds);
  std::vector<PlannedView> plan;
  TrialResult result;
  for (int v = 0; v < options.views; ++v) {
    plan.push_back(PlanView(setup, &rng));
    result.views.push_back(plan.back().conditions);
  }
  const auto start = Clock::now();
  const std::vector<cv::Mat> frames = Render(setup, plan, options.render_threads);
  result.render_s = Milliseconds(start) / 1000;
  result.outcome[kChromaTagBoard] = CalibrateWithChromaTag(setup, plan, frames);
  result.outcome[kCharucoBoard] = CalibrateWithCharuco(setup, plan, frames);
  return result;
}

}  // namespace chromatag::bench
