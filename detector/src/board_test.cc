#include "chromatag/detector/board.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"
#include "chromatag/detector/pose.h"

namespace chromatag {
namespace {

constexpr double kPi = 3.14159265358979323846;

CameraIntrinsics Camera() {
  CameraIntrinsics camera;
  camera.fx = camera.fy = 800;
  camera.cx = 640;
  camera.cy = 480;
  return camera;
}

// A cols x rows grid of 16h5 tags of side `size`, `pitch` apart, ID i at
// column i % cols and row i / cols from the top; the board frame's origin at
// the grid's centre, x right, y up.
Board Grid(int cols, int rows, double size, double pitch) {
  Board board;
  board.name = "grid";
  const std::vector<int>& kept = TagFamily::Load("16h5")->kept_ids();
  for (int i = 0; i < cols * rows; ++i) {
    BoardTag tag;
    tag.family = "16h5";
    tag.id = kept[i];
    tag.size = size;
    tag.translation = {((i % cols) - (cols - 1) / 2.0) * pitch,
                       ((rows - 1) / 2.0 - (i / cols)) * pitch, 0};
    board.tags.push_back(tag);
  }
  return board;
}

cv::Matx33d Rotation(const cv::Vec3d& rvec) {
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  return r;
}

// A detection of `tag` where camera_from_board (r, t) puts it, as the
// detector reports it (its corners where straight lines through the sides
// meet, CornerBend), its corners moved by Gaussian noise of `noise` pixels.
Detection Seen(const BoardTag& tag, int id, const cv::Matx33d& r, const cv::Vec3d& t,
               const CameraIntrinsics& camera, double noise, std::mt19937* rng) {
  static const auto family = TagFamily::Load("16h5");
  Detection d;
  d.family = family.get();
  d.id = id;
  std::normal_distribution<double> gauss(0.0, noise);
  const std::vector<cv::Point3d> corners = BoardTagCorners(tag, *family);
  cv::Vec3d rvec;
  cv::Rodrigues(r, rvec);
  const std::vector<cv::Point2d> image = ProjectPoints(camera, corners, rvec, t);
  const std::vector<cv::Point2d> bend = CornerBend(camera, corners, rvec, t);
  for (int i = 0; i < 12; ++i) {
    cv::Point2d q = image[i] + bend[i];
    if (noise > 0) q += cv::Point2d(gauss(*rng), gauss(*rng));
    (i < 4 ? d.corners : i < 8 ? d.green_corners : d.red_corners)[i % 4] = q;
  }
  return d;
}

double DegreesApart(const cv::Vec3d& rvec, const cv::Matx33d& truth) {
  cv::Vec3d apart;
  cv::Rodrigues(cv::Matx33d(Rotation(rvec).t() * truth), apart);
  return cv::norm(apart) * 180 / kPi;
}

// Through a pinhole camera and a fisheye lens alike, from corners as the
// detector reports them without noise.
TEST(BoardTest, ExactCornersGiveThePoseAtEveryView) {
  const Board board = Grid(4, 3, 0.04, 0.05);
  CameraIntrinsics fisheye = Camera();
  fisheye.model = LensModel::kFisheye;
  fisheye.distortion = {0.05, -0.02, 0.01, -0.002};
  for (const CameraIntrinsics& camera : {Camera(), fisheye}) {
    // Face-on (the board frame at 180 degrees about x from the camera's, where
    // a Rodrigues vector is singular), turned a quarter, and tilted to 70.
    for (const cv::Vec3d& rvec : {cv::Vec3d(kPi, 0, 0), cv::Vec3d(kPi, 0, 0.5 * kPi),
                                  cv::Vec3d(2.6, 0.4, 0.3), cv::Vec3d(kPi * 0.61, 0, 0)}) {
      const cv::Matx33d r = Rotation(rvec);
      const cv::Vec3d t(0.03, -0.02, 0.6);
      std::vector<Detection> detections;
      for (const BoardTag& tag : board.tags)
        detections.push_back(Seen(tag, tag.id, r, t, camera, 0, nullptr));
      BoardPose pose;
      std::string error;
      ASSERT_TRUE(EstimateBoardPose(detections, board, camera, &pose, &error)) << error;
      // Through the fisheye lens the corners are straightened once, under
      // the first pose: a few millionths of a pixel are left.
      EXPECT_LT(DegreesApart(pose.rvec, r), 1e-5);
      EXPECT_LT(cv::norm(pose.tvec - t), 1e-7);
      EXPECT_LE(cv::norm(pose.rvec), kPi + 1e-12);
      EXPECT_LT(pose.rms_error_px, 1e-5);
      EXPECT_EQ(pose.tags_used.size(), board.tags.size());
      EXPECT_TRUE(pose.detections_rejected.empty());
    }
  }
}

// A tag seen where another belongs (a misread ID, or the board file wrong
// about it) is left out and named; the pose stays on the others.
TEST(BoardTest, AMisplacedTagIsLeftOutAndNamed) {
  const Board board = Grid(4, 3, 0.04, 0.05);
  const CameraIntrinsics camera = Camera();
  const cv::Matx33d r = Rotation({2.7, 0.3, 0.1});
  const cv::Vec3d t(-0.02, 0.01, 0.8);
  std::mt19937 rng(7);
  std::vector<Detection> detections;
  for (size_t i = 0; i < board.tags.size(); ++i) {
    // Tag 5's place shows tag 9's ID (tag 9 itself hidden).
    if (i == 9) continue;
    const int id = i == 5 ? board.tags[9].id : board.tags[i].id;
    detections.push_back(Seen(board.tags[i], id, r, t, camera, 0.2, &rng));
  }
  BoardPose pose;
  std::string error;
  ASSERT_TRUE(EstimateBoardPose(detections, board, camera, &pose, &error)) << error;
  EXPECT_LT(DegreesApart(pose.rvec, r), 0.2);
  EXPECT_LT(cv::norm(pose.tvec - t) / cv::norm(t), 0.002);
  // The detection at tag 5's place, ID of tag 9: left out, tag 9 unused.
  ASSERT_EQ(pose.detections_rejected, std::vector<int>{5});
  EXPECT_EQ(detections[5].id, board.tags[9].id);
  EXPECT_EQ(pose.tags_used.size(), board.tags.size() - 2);
  EXPECT_EQ(std::count(pose.tags_used.begin(), pose.tags_used.end(), 9), 0);
  EXPECT_LT(pose.rms_error_px, 0.5);
}

// A single tag's pose, from its corners as the detector reports them
// through the lens (no noise): the corners straightened once under the
// first pose leave a few ten-thousandths of a pixel (as detected, the
// fisheye's bend cost up to 0.25 degrees and 0.06 mm).
TEST(BoardTest, ExactCornersGiveATagsPoseThroughTheLens) {
  const Board board = Grid(4, 3, 0.04, 0.05);
  CameraIntrinsics fisheye = Camera();
  fisheye.model = LensModel::kFisheye;
  fisheye.distortion = {0.05, -0.02, 0.01, -0.002};
  for (const CameraIntrinsics& camera : {Camera(), fisheye}) {
    for (const cv::Vec3d& rvec : {cv::Vec3d(kPi, 0, 0), cv::Vec3d(2.6, 0.4, 0.3)}) {
      const cv::Matx33d r = Rotation(rvec);
      const cv::Vec3d t(0.03, -0.02, 0.3);
      const BoardTag& tag = board.tags[0];  // In a corner of the board, far from the middle.
      TagPose pose;
      ASSERT_TRUE(
          EstimateTagPose(Seen(tag, tag.id, r, t, camera, 0, nullptr), camera, tag.size, &pose));
      EXPECT_LT(DegreesApart(pose.rvec, r * tag.rotation), 1e-4);
      EXPECT_LT(cv::norm(pose.tvec - (r * tag.translation + t)), 1e-6);
      EXPECT_LT(pose.rms_error_px, 1e-3);
    }
  }
}

// One tag is enough, and gives that tag's own pose carried to the board.
TEST(BoardTest, OneTagGivesItsOwnPoseCarriedToTheBoard) {
  const Board board = Grid(4, 3, 0.04, 0.05);
  const CameraIntrinsics camera = Camera();
  const cv::Matx33d r = Rotation({2.4, -0.5, 0.2});
  const cv::Vec3d t(0.05, 0.0, 0.5);
  std::mt19937 rng(3);
  const BoardTag& tag = board.tags[6];
  const Detection seen = Seen(tag, tag.id, r, t, camera, 0.3, &rng);
  BoardPose pose;
  ASSERT_TRUE(EstimateBoardPose({seen}, board, camera, &pose));
  EXPECT_EQ(pose.tags_used, std::vector<int>{6});
  TagPose single;
  ASSERT_TRUE(EstimateTagPose(seen, camera, tag.size, &single));
  const cv::Matx33d board_r = Rotation(single.rvec) * tag.rotation.t();
  EXPECT_LT(DegreesApart(pose.rvec, board_r), 1e-4);
  EXPECT_LT(cv::norm(pose.tvec - (single.tvec - board_r * tag.translation)), 1e-6);
  EXPECT_NEAR(pose.rms_error_px, single.rms_error_px, 1e-6);
}

// A bundle that is not planar: tags on three faces of a 10 cm cube.
TEST(BoardTest, ABundleOnACubeGivesItsPose) {
  Board cube;
  const cv::Vec3d faces[3] = {{0, 0, 0}, {0, kPi / 2, 0}, {-kPi / 2, 0, 0}};
  for (int i = 0; i < 3; ++i) {
    BoardTag tag;
    tag.family = "16h5";
    tag.id = i;
    tag.size = 0.06;
    tag.rotation = Rotation(faces[i]);
    tag.translation = tag.rotation * cv::Vec3d(0, 0, 0.05);
    cube.tags.push_back(tag);
  }
  ASSERT_TRUE(cube.IsValid());
  const CameraIntrinsics camera = Camera();
  // Seen from a corner, so that all three faces turn towards the camera: the
  // camera looks along -(1, 1, 1) of the cube's frame (rows: the camera's
  // axes in the cube's frame).
  const cv::Vec3d z = -cv::normalize(cv::Vec3d(1, 1, 1)), x = cv::normalize(cv::Vec3d(1, -1, 0)),
                  y = z.cross(x);
  const cv::Matx33d r(x[0], x[1], x[2], y[0], y[1], y[2], z[0], z[1], z[2]);
  const cv::Vec3d t(0, 0, 0.7);
  std::mt19937 rng(11);
  std::vector<Detection> detections;
  for (const BoardTag& tag : cube.tags) {
    const cv::Vec3d normal = r * tag.rotation * cv::Vec3d(0, 0, 1);
    if (normal[2] < -0.3) detections.push_back(Seen(tag, tag.id, r, t, camera, 0.2, &rng));
  }
  ASSERT_EQ(detections.size(), 3u);
  BoardPose pose;
  std::string error;
  ASSERT_TRUE(EstimateBoardPose(detections, cube, camera, &pose, &error)) << error;
  EXPECT_LT(DegreesApart(pose.rvec, r), 0.3);
  EXPECT_LT(cv::norm(pose.tvec - t) / cv::norm(t), 0.003);
  EXPECT_EQ(pose.tags_used.size(), detections.size());
}

TEST(BoardTest, RefusesABadBoardAndNoTagOfIt) {
  Board board = Grid(2, 2, 0.04, 0.05);
  std::string error;
  Board twice = board;
  twice.tags[3].id = twice.tags[0].id;
  EXPECT_FALSE(twice.IsValid(&error));
  EXPECT_NE(error.find("twice"), std::string::npos) << error;
  Board skewed = board;
  skewed.tags[1].rotation(0, 1) = 0.3;
  EXPECT_FALSE(skewed.IsValid(&error));
  EXPECT_NE(error.find("not a rotation"), std::string::npos) << error;
  Board unknown = board;
  unknown.tags[2].family = "25h9";
  EXPECT_FALSE(unknown.IsValid(&error));
  EXPECT_NE(error.find("16h5 or 36h11"), std::string::npos) << error;
  Board flat = board;
  flat.tags[0].size = 0;
  EXPECT_FALSE(flat.IsValid(&error));
  Board rejected_id = board;
  rejected_id.tags[0].id = 5;  // 16h5 does not keep ID 5.
  EXPECT_FALSE(rejected_id.IsValid(&error));
  EXPECT_NE(error.find("16h5 ID 5"), std::string::npos) << error;
  EXPECT_FALSE(Board{}.IsValid(&error));

  const CameraIntrinsics camera = Camera();
  std::mt19937 rng(1);
  BoardTag stranger = board.tags[0];
  stranger.id = 20;
  const Detection other = Seen(stranger, 20, Rotation({kPi, 0, 0}), {0, 0, 0.5}, camera, 0, &rng);
  BoardPose pose;
  EXPECT_FALSE(EstimateBoardPose({other}, board, camera, &pose, &error));
  EXPECT_NE(error.find("none of the board's 4 tags"), std::string::npos) << error;
  EXPECT_FALSE(EstimateBoardPose({}, board, CameraIntrinsics{}, &pose, &error));
}

}  // namespace
}  // namespace chromatag
