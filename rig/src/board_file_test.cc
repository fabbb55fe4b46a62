#include "chromatag/rig/board_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "chromatag/generator/sheet.h"

namespace chromatag {
namespace {

// apriltag_ros's tags.yaml shape (flow style, as its docs write it), with
// the family for the bundle.
constexpr const char* kTwoBundles = R"(
standalone_tags: []
tag_bundles:
  [
    {
      name: 'robot',
      family: 16h5,
      palette: iccv17,
      layout:
        [
          {id: 3, size: 0.05, x: 0.0, y: 0.0, z: 0.0, qw: 1.0, qx: 0.0, qy: 0.0, qz: 0.0},
          {id: 7, size: 0.05, x: 0.1, y: 0.0, z: -0.02, qw: 0.7071068, qx: 0.0, qy: 0.7071068, qz: 0.0},
          {id: 2, family: tag36h11, size: 0.08, x: 0.0, y: 0.2, z: 0.0}
        ]
    },
    {
      name: 'cart',
      family: 36h11,
      layout: [{id: 0, size: 0.1, x: 0, y: 0, z: 0, qw: 1, qx: 0, qy: 0, qz: 0}]
    }
  ]
)";

TEST(BoardFileTest, ReadsApriltagRosBundles) {
  std::string error;
  EXPECT_FALSE(ParseBundleYaml(kTwoBundles, "", &error));
  EXPECT_EQ(error, "holds 2 bundles ('robot', 'cart'): choose one with FILE#NAME");
  const auto robot = ParseBundleYaml(kTwoBundles, "robot", &error);
  ASSERT_TRUE(robot) << error;
  EXPECT_EQ(robot->name, "robot");
  EXPECT_EQ(robot->palette, "iccv17");
  ASSERT_EQ(robot->tags.size(), 3u);
  EXPECT_EQ(robot->tags[0].family, "16h5");
  EXPECT_EQ(robot->tags[2].family, "36h11");  // "tag36h11", as apriltag names it.
  EXPECT_EQ(robot->tags[1].id, 7);
  EXPECT_DOUBLE_EQ(robot->tags[1].size, 0.05);
  EXPECT_EQ(robot->tags[1].translation, cv::Vec3d(0.1, 0.0, -0.02));
  // A quarter turn about y: the tag's z axis along the bundle's x.
  const cv::Vec3d z = robot->tags[1].rotation * cv::Vec3d(0, 0, 1);
  EXPECT_NEAR(z[0], 1.0, 1e-6);
  EXPECT_NEAR(z[2], 0.0, 1e-6);
  // No quaternion: the bundle's own axes.
  EXPECT_EQ(robot->tags[2].rotation, cv::Matx33d::eye());
  EXPECT_FALSE(ParseBundleYaml(kTwoBundles, "boat", &error));
  EXPECT_EQ(error, "has no bundle 'boat' (it holds 'robot', 'cart')");
  // ROS 2 parameter files nest it under the node.
  const auto nested = ParseBundleYaml(
      "apriltag:\n  ros__parameters:\n    tag_bundles:\n      - name: b\n        family: 16h5\n"
      "        layout:\n          - {id: 1, size: 0.04, x: 0, y: 0, z: 0}\n",
      "", &error);
  ASSERT_TRUE(nested) << error;
  EXPECT_EQ(nested->tags[0].id, 1);

  // FILE#NAME through ReadBoardFile.
  const std::string path = ::testing::TempDir() + "/bundles.yaml";
  std::ofstream(path) << kTwoBundles;
  const auto cart = ReadBoardFile(path + "#cart", &error);
  ASSERT_TRUE(cart) << error;
  EXPECT_EQ(cart->tags[0].family, "36h11");
  EXPECT_FALSE(ReadBoardFile(path, &error));
  EXPECT_EQ(error, "board file '" + path +
                       "' holds 2 bundles ('robot', 'cart'): choose one with FILE#NAME");
}

TEST(BoardFileTest, RefusesBrokenBundlesSayingWhat) {
  std::string error;
  const auto refused = [&](const std::string& layout, const std::string& what) {
    const std::string text = "tag_bundles:\n  - name: b\n    family: 16h5\n    layout:\n" + layout;
    EXPECT_FALSE(ParseBundleYaml(text, "", &error)) << layout;
    EXPECT_NE(error.find(what), std::string::npos) << error;
  };
  refused("      - {id: 1, x: 0, y: 0, z: 0}\n", "tag 1 has no size");
  refused("      - {id: 1, x: 0, y: 0, z: 0}\n      - {id: 2, size: 0.04}\n", "tag 1 has no size");
  refused("      - {id: 1, size: -1, x: 0, y: 0, z: 0}\n",
          "the size -1 m is out of range (0.001 to 10 m)");
  // Values no fit can use are refused before any work, naming the range.
  refused("      - {id: 1, size: 1e300, x: 0, y: 0, z: 0}\n", "the size 1e+300 m is out of range");
  refused("      - {id: 1, size: 0.04, x: 1e12, y: 0, z: 0}\n",
          "the position's x, 1e+12 m, is out of range (at most 1000 m from the board's origin)");
  refused("      - {id: 1, size: 0.04, x: 0, y: 0, z: 0, qw: 2}\n", "unit quaternion");
  refused("      - {id: 1, size: 0.04, x: 0, y: 0, z: abc}\n", "z is not a number");
  refused("      - {id: 1.5, size: 0.04, x: 0, y: 0, z: 0}\n", "whole number");
  refused(
      "      - {id: 1, size: 0.04, x: 0, y: 0, z: 0}\n      - {id: 1, size: 0.04, x: 1, y: 0, "
      "z: 0}\n",
      "on the board twice");
  refused("      - {id: 1, family: 25h9, size: 0.04, x: 0, y: 0, z: 0}\n", "16h5 or 36h11");
  refused("      []\n", "has no layout");
  EXPECT_FALSE(
      ParseBundleYaml("tag_bundles:\n  - name: b\n    layout:\n      - {id: 1, size: "
                      "0.04, x: 0, y: 0, z: 0}\n",
                      "", &error));
  EXPECT_NE(error.find("has no family"), std::string::npos) << error;
  EXPECT_FALSE(ParseBundleYaml("standalone_tags: []\n", "", &error));
  EXPECT_NE(error.find("has no tag_bundles"), std::string::npos) << error;
  EXPECT_FALSE(ParseBundleYaml("tag_bundles: [ {", "", &error));
  EXPECT_NE(error.find("is not valid YAML"), std::string::npos) << error;
  EXPECT_FALSE(ReadBoardFile("/nonexistent/board.yaml", &error));
  EXPECT_NE(error.find("cannot read board file '/nonexistent/board.yaml'"), std::string::npos)
      << error;
  EXPECT_FALSE(ReadBoardFile("board.txt", &error));
  EXPECT_NE(error.find("its sidecar (.json) or a bundle YAML"), std::string::npos) << error;
}

// A sheet's sidecar: every tag at its place on the page, in metres, y up
// from the page's bottom-left corner; a sheet of several pages is refused.
TEST(BoardFileTest, ASheetIsABoardOfOnePage) {
  SheetOptions options;
  std::string error;
  options.family = TagFamily::Load("16h5");
  options.ids = {0, 1, 2, 3};
  options.palette = *BuiltinPalette("default");
  const std::string path = ::testing::TempDir() + "/board_sheet.pdf";
  ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
  const auto layout = LayoutSheet(options);
  const auto board = ReadBoardFile(SidecarPath(path), &error);
  ASSERT_TRUE(board) << error;
  EXPECT_EQ(board->name, "board_sheet.pdf");
  // The sheet file stands for its sidecar, and gives the same board.
  const auto from_sheet = ReadBoardFile(path, &error);
  ASSERT_TRUE(from_sheet) << error;
  EXPECT_EQ(from_sheet->name, board->name);
  ASSERT_EQ(from_sheet->tags.size(), 4u);
  EXPECT_EQ(from_sheet->tags[3].translation, board->tags[3].translation);
  EXPECT_EQ(board->palette, "default");
  ASSERT_EQ(board->tags.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(board->tags[i].size, 0.04);
    EXPECT_NEAR(board->tags[i].translation[0], layout->tags[i].center_mm[0] / 1000, 1e-6);
    EXPECT_NEAR(board->tags[i].translation[1], (297.0 - layout->tags[i].center_mm[1]) / 1000, 1e-6);
    EXPECT_EQ(board->tags[i].translation[2], 0.0);
  }
  options.one_per_page = true;
  ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
  EXPECT_FALSE(ReadBoardFile(SidecarPath(path), &error));
  EXPECT_NE(error.find("a board is one page of tags, and this sheet has 4 pages"),
            std::string::npos)
      << error;
}

// A bundle whose layout is built from anchors' aliases (3,000 aliases of a
// list of 3,000 tags) is refused at the first alias, before its tags are
// walked; ROS bundle files never use them.
TEST(BoardFileTest, RefusesAliases) {
  std::string bomb = "t: &t {id: 0, family: 16h5, size: 0.05, x: 0, y: 0, z: 0}\nl: &l [";
  for (int i = 0; i < 3000; ++i) bomb += i ? ",*t" : "*t";
  bomb += "]\ntag_bundles:\n  - name: b\n    layout: [";
  for (int i = 0; i < 3000; ++i) bomb += i ? ",*l" : "*l";
  bomb += "]\n";
  std::string error;
  EXPECT_FALSE(ParseBundleYaml(bomb, "", &error));
  EXPECT_NE(error.find("is not valid YAML (line 2: an alias (*name)"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag
