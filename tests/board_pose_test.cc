// Board pose end to end: a board written by the generator (generate
// --board), its sidecar read as the board file, the page warped into a
// pinhole camera's view at known poses, through blur, noise and JPEG, and
// the board's pose from the detections against the truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detector.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/sheet_request.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/rig/board_file.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kWidth = 1280, kHeight = 960;
constexpr double kFocal = 1000;

CameraIntrinsics Camera() {
  CameraIntrinsics camera;
  camera.fx = camera.fy = kFocal;
  camera.cx = (kWidth - 1) / 2.0;
  camera.cy = (kHeight - 1) / 2.0;
  return camera;
}

// A 6 x 4 board of 80 mm 16h5 tags as `generate --board 6x4 --size 80mm`
// writes it, at 4 pixels per mm, with tag `replace` printed as ID
// `replace_id` (a misprint or a misread), and the tags in `hidden` covered.
struct PrintedBoard {
  cv::Mat page;  // BGR.
  double px_per_mm = 0;
  Board board;
  std::array<double, 2> origin_mm{};
};

PrintedBoard PrintBoard(int replace = -1, int replace_id = -1,
                        const std::vector<int>& hidden = {}) {
  SheetRequest request;
  request.board = "6x4";
  request.size = "80mm";
  request.page = "720x520mm";
  request.format = "png";
  request.dpi = 4 * 25.4;
  SheetOptions options;
  std::string error;
  EXPECT_TRUE(ToSheetOptions(request, "board.png", &options, &error)) << error;
  const Board board_as_written = [&] {
    const auto files = RenderSheet(options, "board.png", &error);
    EXPECT_TRUE(files) << error;
    auto record = ParseSidecar(files->back().contents, "", &error);
    EXPECT_TRUE(record) << error;
    auto board = BoardFromSheet(*record, &error);
    EXPECT_TRUE(board) << error;
    return *board;
  }();
  if (replace >= 0) options.ids[replace] = replace_id;
  const auto files = RenderSheet(options, "board.png", &error);
  PrintedBoard printed;
  const std::string& png = files->front().contents;
  printed.page = cv::imdecode(std::vector<uchar>(png.begin(), png.end()), cv::IMREAD_COLOR);
  printed.px_per_mm = options.dpi / 25.4;
  printed.board = board_as_written;
  const auto record = ParseSidecar(files->back().contents, "", &error);
  printed.origin_mm = record->board_origin_mm;
  for (int i : hidden) {
    const PlacedTag& tag = record->tags[i];
    const double pad = 0.25 * options.tag_size_mm;
    cv::rectangle(printed.page,
                  cv::Point2d((tag.corners_mm[0][0] - pad) * printed.px_per_mm,
                              (tag.corners_mm[0][1] - pad) * printed.px_per_mm),
                  cv::Point2d((tag.corners_mm[2][0] + pad) * printed.px_per_mm,
                              (tag.corners_mm[2][1] + pad) * printed.px_per_mm),
                  cv::Scalar(120, 110, 100), cv::FILLED);
  }
  return printed;
}

struct View {
  cv::Matx33d rotation;  // camera_from_board.
  cv::Vec3d translation;
  double distance = 0;  // Of the board's centre.
};

// The board's centre `distance` metres ahead, tilted by `tilt` degrees
// about an in-plane axis at `axis` degrees and turned `spin` degrees in its
// plane.
View MakeView(const Board& board, double distance, double tilt, double axis, double spin) {
  cv::Vec3d centre(0, 0, 0);
  for (const BoardTag& tag : board.tags) centre += tag.translation / double(board.tags.size());
  cv::Matx33d face, turn, lean;
  cv::Rodrigues(cv::Vec3d(kPi, 0, 0), face);  // Board z towards the camera.
  cv::Rodrigues(cv::Vec3d(0, 0, spin * kPi / 180), turn);
  const double a = axis * kPi / 180;
  cv::Rodrigues(cv::Vec3d(std::cos(a), std::sin(a), 0) * (tilt * kPi / 180), lean);
  View view;
  view.rotation = lean * face * turn;
  view.translation = cv::Vec3d(0, 0, distance) - view.rotation * centre;
  view.distance = distance;
  return view;
}

// The page seen at `view`: warped at twice the resolution from a copy of the
// page near that scale, averaged down, then the camera's blur, noise and
// JPEG.
cv::Mat Photograph(const PrintedBoard& printed, const View& view, unsigned seed) {
  const double camera_px_per_mm = kFocal / (view.distance * 1000);
  double page_px_per_mm = printed.px_per_mm;
  cv::Mat page = printed.page;
  while (page_px_per_mm > 4 * camera_px_per_mm) {
    cv::Mat smaller;
    cv::resize(page, smaller, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
    page = smaller;
    page_px_per_mm /= 2;
  }
  const double scale_x = double(page.cols) / printed.page.cols * printed.px_per_mm;
  const double scale_y = double(page.rows) / printed.page.rows * printed.px_per_mm;
  // Page pixel centres -> board metres (x right, y up from the origin).
  const cv::Matx33d board_from_page(
      1 / (scale_x * 1000), 0, (0.5 / scale_x - printed.origin_mm[0]) / 1000, 0,
      -1 / (scale_y * 1000), (printed.origin_mm[1] - 0.5 / scale_y) / 1000, 0, 0, 1);
  const cv::Matx33d k(kFocal, 0, (kWidth - 1) / 2.0, 0, kFocal, (kHeight - 1) / 2.0, 0, 0, 1);
  const cv::Matx33d& r = view.rotation;
  const cv::Matx33d plane(r(0, 0), r(0, 1), view.translation[0], r(1, 0), r(1, 1),
                          view.translation[1], r(2, 0), r(2, 1), view.translation[2]);
  const cv::Matx33d hi_from_image(2, 0, 0.5, 0, 2, 0.5, 0, 0, 1);
  cv::Mat hi;
  cv::warpPerspective(page, hi, cv::Mat(hi_from_image * k * plane * board_from_page),
                      cv::Size(2 * kWidth, 2 * kHeight), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar(95, 110, 125));
  cv::Mat frame;
  cv::resize(hi, frame, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_AREA);
  // A colour camera in dim light: exposure 0.6, lens blur, read and shot
  // noise, a Bayer mosaic, JPEG.
  testing::SceneOptions camera;
  camera.linear_camera = true;
  camera.exposure = 0.6;
  camera.blur_sigma = 1.0;
  camera.noise_sigma = 2.0;
  camera.shot_noise = 0.01;
  camera.demosaic = testing::Demosaic::kBilinear;
  camera.jpeg_quality = 80;
  camera.seed = seed;
  testing::ApplyCamera(camera, &frame);
  return frame;
}

double RotationErrorDeg(const cv::Matx33d& r, const cv::Matx33d& truth) {
  cv::Vec3d apart;
  cv::Rodrigues(cv::Matx33d(r.t() * truth), apart);
  return cv::norm(apart) * 180 / kPi;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty()      ? NAN
         : v.size() % 2 ? v[v.size() / 2]
                        : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

struct Errors {
  double degrees = NAN, distance_share = NAN;
};

Errors BoardError(const BoardPose& pose, const View& view) {
  cv::Matx33d r;
  cv::Rodrigues(pose.rvec, r);
  return {RotationErrorDeg(r, view.rotation),
          cv::norm(pose.tvec - view.translation) / view.distance};
}

std::unique_ptr<Detector> MakeDetector(double tag_size) {
  DetectorOptions options;
  options.families = {"16h5"};
  options.camera = Camera();
  options.tag_size = tag_size;
  return Detector::Create(options);
}

std::vector<View> Views(const Board& board) {
  std::vector<View> views;
  int i = 0;
  for (double distance : {0.5, 0.8, 1.1, 1.4, 1.7, 2.0}) {
    for (double tilt : {20.0, 50.0}) {
      views.push_back(MakeView(board, distance, tilt, 30 + 47 * i, 8 * i - 20));
      ++i;
    }
  }
  return views;
}

// A 6 x 4 board from 0.5 to 2 m, tilted 20 and 50 degrees: median rotation
// error at most 0.3 degrees and translation error at most 0.3 % of the
// distance, better than the best single tag's on the same views.
TEST(BoardPoseTest, ABoardIsMoreAccurateThanItsBestTag) {
  const PrintedBoard printed = PrintBoard();
  const Board& board = printed.board;
  ASSERT_EQ(board.tags.size(), 24u);
  const auto detector = MakeDetector(board.tags[0].size);
  const std::vector<View> views = Views(board);
  std::vector<double> board_degrees, board_shares;
  std::map<int, std::vector<double>> tag_degrees, tag_shares;  // By board tag.
  for (size_t v = 0; v < views.size(); ++v) {
    const View& view = views[v];
    const cv::Mat frame = Photograph(printed, view, static_cast<unsigned>(v + 1));
    const DetectionResult result = detector->Detect(frame);
    BoardPose pose;
    std::string error;
    ASSERT_TRUE(EstimateBoardPose(result.detections, board, Camera(), &pose, &error))
        << "view " << v << ": " << error;
    // Every tag found is used (the closest views cut some off).
    EXPECT_EQ(pose.tags_used.size(), result.detections.size()) << "view " << v;
    EXPECT_GE(pose.tags_used.size(), 12u) << "view " << v;
    EXPECT_TRUE(pose.detections_rejected.empty()) << "view " << v;
    const Errors e = BoardError(pose, view);
    board_degrees.push_back(e.degrees);
    board_shares.push_back(e.distance_share);
    // Each tag's own pose, carried to the board frame.
    for (const Detection& d : result.detections) {
      const int index = board.Find(d.family->name(), d.id);
      ASSERT_GE(index, 0);
      ASSERT_TRUE(d.has_pose);
      const BoardTag& tag = board.tags[index];
      cv::Matx33d r;
      cv::Rodrigues(d.pose.rvec, r);
      const cv::Matx33d board_r = r * tag.rotation.t();
      const cv::Vec3d board_t = d.pose.tvec - board_r * tag.translation;
      tag_degrees[index].push_back(RotationErrorDeg(board_r, view.rotation));
      tag_shares[index].push_back(cv::norm(board_t - view.translation) / view.distance);
    }
  }
  double best_tag_degrees = 1e9, best_tag_share = 1e9;
  for (const auto& [index, degrees] : tag_degrees) {
    if (degrees.size() < views.size() / 2) continue;
    best_tag_degrees = std::min(best_tag_degrees, Median(degrees));
    best_tag_share = std::min(best_tag_share, Median(tag_shares[index]));
  }
  const double degrees = Median(board_degrees), share = Median(board_shares);
  EXPECT_LE(degrees, 0.3);
  EXPECT_LE(share, 0.003);
  EXPECT_LT(degrees, best_tag_degrees);
  EXPECT_LT(share, best_tag_share);
  std::printf("board: median %.3f deg, %.3f %% of distance; best single tag %.3f deg, %.3f %%\n",
              degrees, 100 * share, best_tag_degrees, 100 * best_tag_share);
}

// One tag printed with another board tag's ID: that detection is left out
// and the pose stays right. Three quarters of the board covered: the
// quarter left gives the pose.
TEST(BoardPoseTest, AMisprintedTagOrThreeQuartersHiddenLeaveThePoseRight) {
  const PrintedBoard misprinted = PrintBoard(/*replace=*/8, /*replace_id=*/0);
  // All but the bottom-left 3 x 2 block (tags 12-14, 18-20) hidden.
  std::vector<int> hidden;
  for (int i = 0; i < 24; ++i)
    if (!(i / 6 >= 2 && i % 6 < 3)) hidden.push_back(i);
  const PrintedBoard covered = PrintBoard(-1, -1, hidden);
  const auto detector = MakeDetector(0);
  const std::vector<View> views = Views(misprinted.board);
  std::vector<double> misprinted_degrees, misprinted_shares, covered_degrees, covered_shares;
  for (size_t v = 0; v < views.size(); ++v) {
    if (v % 2 == 0) {
      const DetectionResult result =
          detector->Detect(Photograph(misprinted, views[v], static_cast<unsigned>(v + 7)));
      BoardPose pose;
      ASSERT_TRUE(EstimateBoardPose(result.detections, misprinted.board, Camera(), &pose));
      // ID 0 is seen at tag 8's place (and at its own, unless out of view):
      // that detection is left out.
      ASSERT_EQ(pose.detections_rejected.size(), 1u) << "view " << v;
      const Detection& misprint = result.detections[pose.detections_rejected[0]];
      EXPECT_EQ(misprint.id, 0) << "view " << v;
      EXPECT_EQ(std::count(pose.tags_used.begin(), pose.tags_used.end(), 8), 0) << "view " << v;
      const Errors e = BoardError(pose, views[v]);
      misprinted_degrees.push_back(e.degrees);
      misprinted_shares.push_back(e.distance_share);
    }
    {
      const DetectionResult result =
          detector->Detect(Photograph(covered, views[v], static_cast<unsigned>(v + 9)));
      BoardPose pose;
      ASSERT_TRUE(EstimateBoardPose(result.detections, covered.board, Camera(), &pose));
      EXPECT_LE(pose.tags_used.size(), 6u);
      EXPECT_GE(pose.tags_used.size(), 4u) << "view " << v;
      const Errors e = BoardError(pose, views[v]);
      covered_degrees.push_back(e.degrees);
      covered_shares.push_back(e.distance_share);
    }
  }
  EXPECT_LE(Median(misprinted_degrees), 0.3);
  EXPECT_LE(Median(misprinted_shares), 0.003);
  EXPECT_LE(Median(covered_degrees), 0.5);
  EXPECT_LE(Median(covered_shares), 0.005);
  std::printf("misprinted: %.3f deg, %.3f %%; three quarters hidden: %.3f deg, %.3f %%\n",
              Median(misprinted_degrees), 100 * Median(misprinted_shares), Median(covered_degrees),
              100 * Median(covered_shares));
}

}  // namespace
}  // namespace chromatag
