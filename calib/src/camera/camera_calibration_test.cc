#include "chromatag/calib/camera_calibration.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"
#include "page_view.h"

namespace chromatag {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A 6 x 4 board of 40 mm 16h5 tags, 50 mm apart, origin at its centre.
Board Grid() {
  Board board;
  const std::vector<int>& kept = TagFamily::Load("16h5")->kept_ids();
  for (int i = 0; i < 24; ++i) {
    BoardTag tag;
    tag.family = "16h5";
    tag.id = kept[i];
    tag.size = 0.04;
    tag.translation = {((i % 6) - 2.5) * 0.05, (1.5 - (i / 6)) * 0.05, 0};
    board.tags.push_back(tag);
  }
  return board;
}

// The calibration tests' camera (page_view.h): 752 x 480, fx 600, strong
// barrel distortion (k1 -0.25).
CameraIntrinsics Pinhole() { return testing::BarrelCamera(); }

// The board seen by `camera` as the detector reports it: the black
// square's corners where straight lines through its sides (bent by the
// lens) meet, moved by Gaussian noise of 0.1 px, and the inner corners
// placed from them by the square's homography; tags not wholly in the image
// are not seen. `id_of` may print a tag with another ID.
CalibrationView View(const Board& board, const cv::Vec3d& rvec, const cv::Vec3d& tvec,
                     std::mt19937* rng, std::map<int, int> id_of = {},
                     const CameraIntrinsics& camera = Pinhole()) {
  static const auto family = TagFamily::Load("16h5");
  std::normal_distribution<double> noise(0, 0.1);
  CalibrationView view;
  for (size_t i = 0; i < board.tags.size(); ++i) {
    const std::vector<cv::Point3d> corners = BoardTagCorners(board.tags[i], *family);
    const std::vector<cv::Point2d> image = ProjectPoints(camera, corners, rvec, tvec);
    bool inside = true;
    for (const cv::Point2d& p : image) inside &= p.x > 2 && p.y > 2 && p.x < 750 && p.y < 478;
    if (!inside) continue;
    Detection det;
    det.family = family.get();
    det.id = id_of.count(static_cast<int>(i)) ? id_of[static_cast<int>(i)] : board.tags[i].id;
    const std::vector<cv::Point2d> bend = CornerBend(camera, corners, rvec, tvec);
    std::array<cv::Point2d, 4> outer;
    for (int c = 0; c < 4; ++c) {
      const double dx = noise(*rng), dy = noise(*rng);
      outer[c] = det.corners[c] = image[c] + bend[c] + cv::Point2d(dx, dy);
    }
    const std::vector<cv::Point2d> inner = PlaceInnerCorners(outer, InnerCornersInSquare(corners));
    for (int c = 0; c < 8; ++c) (c < 4 ? det.green_corners : det.red_corners)[c % 4] = inner[c];
    view.detections.push_back(det);
  }
  return view;
}

// The board facing the camera, tilted by `tilt_deg` about an axis at
// `axis` radians in the image plane.
cv::Vec3d Tilted(double axis, double tilt_deg) {
  cv::Matx33d lean, face;
  cv::Rodrigues(cv::Vec3d(std::cos(axis), std::sin(axis), 0) * (tilt_deg * kPi / 180), lean);
  cv::Rodrigues(cv::Vec3d(kPi, 0, 0), face);
  cv::Vec3d rvec;
  cv::Rodrigues(lean * face, rvec);
  return rvec;
}

// `n` views, named "view 0"...: tilted 10-45 degrees about varied axes,
// 0.3 to 0.6 m away; `misprints` (view -> board tag index -> the ID
// printed there) as View's `id_of`. Their poses go to *poses if given.
std::vector<CalibrationView> VariedViews(const Board& board, int n, std::mt19937* rng,
                                         std::vector<std::pair<cv::Vec3d, cv::Vec3d>>* poses,
                                         const std::map<int, std::map<int, int>>& misprints = {}) {
  std::uniform_real_distribution<double> angle(0, 2 * kPi), tilt(10, 45), depth(0.3, 0.6),
      shift(-0.05, 0.05);
  std::vector<CalibrationView> views;
  for (int v = 0; v < n; ++v) {
    const cv::Vec3d rvec = Tilted(angle(*rng), tilt(*rng));
    const cv::Vec3d tvec{shift(*rng), shift(*rng), depth(*rng)};  // In this order.
    const auto misprint = misprints.find(v);
    views.push_back(View(board, rvec, tvec, rng,
                         misprint == misprints.end() ? std::map<int, int>{} : misprint->second));
    views.back().name = "view " + std::to_string(v);
    if (poses) poses->push_back({rvec, tvec});
  }
  return views;
}

// Twenty views tilted up to 45 degrees about varied axes, 0.3 to 0.6 m away:
// fx and fy within 0.1 %, the principal point within 1 px, k1 within 0.005,
// rms at most 0.2 px. A view with one tag printed with another board tag's
// ID uses the others, naming it; a view of another board is not used.
TEST(CameraCalibrationTest, RecoversTheCameraFromViewsOfABoard) {
  const Board board = Grid();
  std::mt19937 rng(4);
  std::vector<CalibrationView> views =
      VariedViews(board, 20, &rng, nullptr, {{7, {{9, board.tags[14].id}}}});
  Board other = board;
  for (BoardTag& tag : other.tags) tag.translation *= 1.3;
  CalibrationView wrong = View(other, cv::Vec3d(kPi, 0, 0), {0, 0, 0.5}, &rng);
  for (Detection& d : wrong.detections) d.id = TagFamily::Load("16h5")->kept_ids()[27];
  wrong.name = "another board";
  views.push_back(wrong);
  std::string error;
  const auto calibration = CalibrateCamera(board, views, {752, 480}, {}, &error);
  ASSERT_TRUE(calibration) << error;
  const CameraIntrinsics& c = calibration->camera;
  EXPECT_NEAR(c.fx, 600, 0.6);
  EXPECT_NEAR(c.fy, 603, 0.6);
  EXPECT_NEAR(c.cx, 370, 1.0);
  EXPECT_NEAR(c.cy, 245, 1.0);
  ASSERT_EQ(c.distortion.size(), 5u);
  EXPECT_NEAR(c.distortion[0], -0.25, 0.005);
  EXPECT_LE(calibration->rms_px, 0.2);
  ASSERT_EQ(calibration->std_dev.size(), 9u);
  EXPECT_LT(calibration->std_dev[0], 0.6);
  ASSERT_EQ(calibration->views.size(), 21u);
  EXPECT_TRUE(calibration->views[7].used);
  EXPECT_EQ(calibration->views[7].tags_left_out, std::vector<int>{board.tags[14].id});
  EXPECT_FALSE(calibration->views[20].used);
  EXPECT_NE(calibration->views[20].why_not.find("board tag"), std::string::npos)
      << calibration->views[20].why_not;
  EXPECT_TRUE(calibration->warnings.empty()) << calibration->warnings[0];
  // Every used corner has its residual, and they make up the rms.
  double sum = 0;
  int n = 0;
  for (const CalibrationViewResult& v : calibration->views) {
    ASSERT_EQ(v.corners.size(), v.residuals.size());
    for (const cv::Point2d& e : v.residuals) sum += e.dot(e);
    n += static_cast<int>(v.residuals.size());
  }
  EXPECT_EQ(n, calibration->corners_used);
  EXPECT_NEAR(std::sqrt(sum / n), calibration->rms_px, 1e-3);
}

// The standard deviations say how far fx and cx move with the corners'
// noise: over ten noise draws on the same views, the spread of the estimates
// matches the deviation the fit reports, within the spread's own
// uncertainty (ten draws: about +-25 %).
TEST(CameraCalibrationTest, StandardDeviationsMatchTheSpread) {
  const Board board = Grid();
  std::mt19937 poses(8);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), tilt(10, 45), depth(0.3, 0.6),
      shift(-0.05, 0.05);
  std::vector<std::pair<cv::Vec3d, cv::Vec3d>> views;
  for (int v = 0; v < 12; ++v)
    views.push_back(
        {Tilted(angle(poses), tilt(poses)), {shift(poses), shift(poses), depth(poses)}});
  std::vector<double> fx, cx, reported_fx, reported_cx;
  for (int draw = 0; draw < 10; ++draw) {
    std::mt19937 rng(100 + draw);
    std::vector<CalibrationView> seen;
    for (const auto& [rvec, tvec] : views) seen.push_back(View(board, rvec, tvec, &rng));
    const auto calibration = CalibrateCamera(board, seen, {752, 480});
    ASSERT_TRUE(calibration);
    fx.push_back(calibration->camera.fx);
    cx.push_back(calibration->camera.cx);
    reported_fx.push_back(calibration->std_dev[0]);
    reported_cx.push_back(calibration->std_dev[2]);
  }
  const auto spread = [](const std::vector<double>& x) {
    double mean = 0, sum = 0;
    for (double v : x) mean += v / x.size();
    for (double v : x) sum += (v - mean) * (v - mean);
    return std::sqrt(sum / (x.size() - 1));
  };
  const auto mean = [](const std::vector<double>& x) {
    double m = 0;
    for (double v : x) m += v / x.size();
    return m;
  };
  EXPECT_GT(spread(fx) / mean(reported_fx), 0.55) << spread(fx) << " " << mean(reported_fx);
  EXPECT_LT(spread(fx) / mean(reported_fx), 1.6) << spread(fx) << " " << mean(reported_fx);
  EXPECT_GT(spread(cx) / mean(reported_cx), 0.55) << spread(cx) << " " << mean(reported_cx);
  EXPECT_LT(spread(cx) / mean(reported_cx), 1.6) << spread(cx) << " " << mean(reported_cx);
}

// cv::fisheye's equidistant model, fx 300 on a wide lens: the same limits.
TEST(CameraCalibrationTest, RecoversAFisheyeCamera) {
  const Board board = Grid();
  CameraIntrinsics lens;
  lens.fx = 300;
  lens.fy = 301;
  lens.cx = 380;
  lens.cy = 236;
  lens.model = LensModel::kFisheye;
  lens.distortion = {-0.02, 0.01, -0.004, 0.001};
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), tilt(10, 45), depth(0.15, 0.3),
      shift(-0.1, 0.1);
  std::vector<CalibrationView> views;
  for (int v = 0; v < 20; ++v) {
    views.push_back(View(board, Tilted(angle(rng), tilt(rng)), {shift(rng), shift(rng), depth(rng)},
                         &rng, {}, lens));
    views.back().name = "view " + std::to_string(v);
  }
  CameraCalibrationOptions options;
  options.model = LensModel::kFisheye;
  std::string error;
  const auto calibration = CalibrateCamera(board, views, {752, 480}, options, &error);
  ASSERT_TRUE(calibration) << error;
  const CameraIntrinsics& c = calibration->camera;
  EXPECT_EQ(c.model, LensModel::kFisheye);
  EXPECT_NEAR(c.fx, 300, 0.3);
  EXPECT_NEAR(c.fy, 301, 0.3);
  EXPECT_NEAR(c.cx, 380, 1.0);
  EXPECT_NEAR(c.cy, 236, 1.0);
  ASSERT_EQ(c.distortion.size(), 4u);
  EXPECT_NEAR(c.distortion[0], -0.02, 0.005);
  EXPECT_LE(calibration->rms_px, 0.2);
  ASSERT_EQ(calibration->std_dev.size(), 8u);
  EXPECT_GT(calibration->std_dev[0], 0.0);
  EXPECT_LT(calibration->std_dev[0], 0.3);
}

// Views that all face the camera from its middle: the calibration says what
// they leave unconstrained, and which parameters are in doubt.
TEST(CameraCalibrationTest, WarnsWhenViewsConstrainLittle) {
  const Board board = Grid();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), tilt(0, 8);
  std::vector<CalibrationView> views;
  for (int v = 0; v < 6; ++v) {
    views.push_back(View(board, Tilted(angle(rng), tilt(rng)), {0, 0, 0.7}, &rng));
    views.back().name = "view " + std::to_string(v);
  }
  std::string error;
  const auto calibration = CalibrateCamera(board, views, {752, 480}, {}, &error);
  ASSERT_TRUE(calibration) << error;
  std::string all;
  for (const std::string& w : calibration->warnings) all += w + "\n";
  // Two of the six lie within a pixel of each other and count once.
  int used = 0;
  for (const CalibrationViewResult& v : calibration->views) used += v.used ? 1 : 0;
  EXPECT_EQ(used, 5);
  EXPECT_NE(all.find("5 views used"), std::string::npos) << all;
  EXPECT_NE(all.find("distortion is weakly constrained"), std::string::npos) << all;
  // No view is tilted: the focal length and principal point are in doubt,
  // and the fit's own deviations put fx in doubt too.
  std::string doubts;
  for (const std::string& d : calibration->doubts) doubts += d + "\n";
  EXPECT_EQ(doubts.rfind("fx, fy, cx and cy are not pinned down: 0 view(s) tilted", 0), 0u)
      << doubts;
  EXPECT_NE(doubts.find("fx is uncertain"), std::string::npos) << doubts;
}

// Twenty views of a flat board: the two halves of the views agree as far
// as their noise says they should. When every other view shows the board
// bent (its middle 1.5 mm nearer the camera than its ends, a sheet curling
// off a table), they disagree beyond that, and the doubt says so. Six views
// of the flat board make halves too small to agree within 0.3 px: that
// doubt says to add views, not that the views disagree.
TEST(CameraCalibrationTest, CrossValidationTellsDisagreeingViewsFromTooFewViews) {
  const Board board = Grid();
  Board bent = board;
  for (BoardTag& tag : bent.tags) {
    const double x = tag.translation[0] / 0.125;  // -1 to 1 along the board.
    tag.translation[2] = 0.0015 * (x * x - 1);    // Board z points away from the camera.
  }
  std::vector<std::pair<cv::Vec3d, cv::Vec3d>> poses;
  std::mt19937 rng(12);
  const std::vector<CalibrationView> flat = VariedViews(board, 20, &rng, &poses);
  std::vector<CalibrationView> curled = flat;
  for (size_t v = 1; v < curled.size(); v += 2) {
    curled[v] = View(bent, poses[v].first, poses[v].second, &rng);
    curled[v].name = flat[v].name;
  }
  const auto all_doubts = [](const CameraCalibration& c) {
    std::string text;
    for (const std::string& d : c.doubts) text += d + "\n";
    return text;
  };
  const auto good = CalibrateCamera(board, flat, {752, 480});
  ASSERT_TRUE(good);
  EXPECT_FALSE(good->projection.cross_validation_beyond_noise);
  EXPECT_EQ(all_doubts(*good).find("do not agree"), std::string::npos) << all_doubts(*good);

  const auto disagreeing = CalibrateCamera(board, curled, {752, 480});
  ASSERT_TRUE(disagreeing);
  EXPECT_TRUE(disagreeing->projection.cross_validation_beyond_noise);
  EXPECT_NE(all_doubts(*disagreeing).find("the views do not agree on the lens"), std::string::npos)
      << all_doubts(*disagreeing);

  const std::vector<CalibrationView> six(flat.begin(), flat.begin() + 6);
  const auto few = CalibrateCamera(board, six, {752, 480});
  ASSERT_TRUE(few);
  EXPECT_FALSE(few->projection.cross_validation_beyond_noise);
  EXPECT_EQ(all_doubts(*few).find("do not agree"), std::string::npos) << all_doubts(*few);
  EXPECT_NE(all_doubts(*few).find("as the corners' noise gives so few views: add views"),
            std::string::npos)
      << all_doubts(*few);
  std::printf("flat: cross-validation worst %.3f px\ncurled:\n%ssix views:\n%s",
              good->projection.cross_validation_worst_px, all_doubts(*disagreeing).c_str(),
              all_doubts(*few).c_str());
}

// A view given twice (an image copied, or a camera that did not move: the
// same pose with fresh noise of 0.1 px on its corners) is used once and
// named: copies would shrink the standard deviations as if they were new
// views. Ten copies of one view are one view, too few to calibrate with.
TEST(CameraCalibrationTest, UsesAViewGivenTwiceOnce) {
  const Board board = Grid();
  std::mt19937 rng(4);
  std::vector<std::pair<cv::Vec3d, cv::Vec3d>> poses;
  std::vector<CalibrationView> views = VariedViews(board, 12, &rng, &poses);
  std::string error;
  const auto distinct = CalibrateCamera(board, views, {752, 480}, {}, &error);
  ASSERT_TRUE(distinct) << error;
  std::vector<CalibrationView> with_copies = views;
  for (int copy = 0; copy < 3; ++copy) {
    // The image itself, then the same pose photographed again.
    with_copies.push_back(copy == 0 ? views[5]
                                    : View(board, poses[5].first, poses[5].second, &rng));
    with_copies.back().name = "copy " + std::to_string(copy);
  }
  const auto calibration = CalibrateCamera(board, with_copies, {752, 480}, {}, &error);
  ASSERT_TRUE(calibration) << error;
  for (int copy = 0; copy < 3; ++copy) {
    const CalibrationViewResult& v = calibration->views[12 + copy];
    EXPECT_FALSE(v.used);
    EXPECT_EQ(v.why_not.rfind("the same view as 'view 5'", 0), 0u) << v.why_not;
  }
  EXPECT_DOUBLE_EQ(calibration->camera.fx, distinct->camera.fx);
  EXPECT_DOUBLE_EQ(calibration->std_dev[0], distinct->std_dev[0]);

  std::vector<CalibrationView> one_view(10, views[3]);
  const auto refused = CalibrateCamera(board, one_view, {752, 480}, {}, &error);
  EXPECT_FALSE(refused);
  EXPECT_NE(error.find("fewer than three views"), std::string::npos) << error;
  EXPECT_NE(error.find("9 the same as another view"), std::string::npos) << error;
}

TEST(CameraCalibrationTest, RefusesWhatCannotCalibrate) {
  Board board = Grid();
  std::mt19937 rng(1);
  std::vector<CalibrationView> two = {View(board, cv::Vec3d(kPi, 0, 0), {0, 0, 0.5}, &rng),
                                      View(board, cv::Vec3d(2.8, 0.3, 0), {0, 0, 0.5}, &rng)};
  std::string error;
  EXPECT_FALSE(CalibrateCamera(board, two, {752, 480}, {}, &error));
  EXPECT_NE(error.find("fewer than three views"), std::string::npos) << error;
  EXPECT_FALSE(CalibrateCamera(board, two, {0, 0}, {}, &error));
  EXPECT_NE(error.find("image size"), std::string::npos) << error;
  board.tags[3].translation[2] = 0.01;
  EXPECT_FALSE(CalibrateCamera(board, two, {752, 480}, {}, &error));
  EXPECT_NE(error.find("planar board"), std::string::npos) << error;
  board = Grid();
  CameraCalibrationOptions options;
  options.model = LensModel::kFisheye;
  options.fit_k3 = true;
  EXPECT_FALSE(CalibrateCamera(board, two, {752, 480}, options, &error));
  EXPECT_NE(error.find("k3 belongs to the pinhole model"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag
