#include "chromatag/families/family.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include <set>

namespace chromatag {
namespace {

std::shared_ptr<const TagFamily> MustLoad(const std::string& name) {
  std::string error;
  auto family = TagFamily::Load(name, &error);
  EXPECT_TRUE(family) << error;
  return family;
}

TEST(TagFamilyTest, Keeps28Of30In16h5AndRejectsIds5And10) {
  auto family = MustLoad("16h5");
  EXPECT_EQ(family->num_apriltag_ids(), 30);
  EXPECT_EQ(family->kept_ids().size(), 28u);
  ASSERT_EQ(family->rejected_ids().size(), 2u);
  EXPECT_EQ(family->rejected_ids()[0].id, 5);
  EXPECT_EQ(family->rejected_ids()[1].id, 10);
  for (const auto& rejected : family->rejected_ids()) {
    EXPECT_NE(rejected.reason.find("red cells are all bit"), std::string::npos) << rejected.reason;
  }
}

TEST(TagFamilyTest, KeepsAll587Of36h11) {
  auto family = MustLoad("36h11");
  EXPECT_EQ(family->num_apriltag_ids(), 587);
  EXPECT_EQ(family->kept_ids().size(), 587u);
  EXPECT_TRUE(family->rejected_ids().empty());
}

TEST(TagFamilyTest, GeometryFollowsSpecSection1) {
  auto f16 = MustLoad("16h5");
  EXPECT_EQ(f16->payload_width(), 4);
  EXPECT_EQ(f16->black_square_cells(), 6);
  EXPECT_EQ(f16->num_red_cells(), 4);
  EXPECT_EQ(f16->num_green_cells(), 12);
  auto f36 = MustLoad("36h11");
  EXPECT_EQ(f36->payload_width(), 6);
  EXPECT_EQ(f36->num_red_cells(), 16);
  EXPECT_EQ(f36->num_green_cells(), 20);
  EXPECT_EQ(f36->CellColorAt(0, 3), CellColor::kGreen);
  EXPECT_EQ(f36->CellColorAt(1, 1), CellColor::kRed);
  EXPECT_EQ(f36->CellColorAt(4, 4), CellColor::kRed);
  EXPECT_EQ(f36->CellColorAt(5, 4), CellColor::kGreen);
}

TEST(TagFamilyTest, Id0Of16h5ReadsAsTheAuthorsSampleTag) {
  // Spec section 2: row-major from the top-left payload cell, MSB first.
  EXPECT_EQ(MustLoad("16h5")->CodeOf(0), Code{0x231b});
}

// Every ID's payload must equal libapriltag's own rendering: white = bit 1.
void ExpectMatchesAprilTagRendering(const std::string& name, apriltag_family_t* april) {
  auto family = MustLoad(name);
  const int d = family->payload_width();
  for (int id = 0; id < family->num_apriltag_ids(); ++id) {
    image_u8_t* image = apriltag_to_image(april, id);
    ASSERT_EQ(image->width, april->total_width);
    const int offset = (image->width - d) / 2;
    // The cells around the payload are AprilTag's black border.
    for (int i = 0; i < d + 2; ++i) {
      EXPECT_EQ(image->buf[(offset - 1) * image->stride + offset - 1 + i], 0);
    }
    const Code code = family->CodeOf(id);
    for (int row = 0; row < d; ++row) {
      for (int col = 0; col < d; ++col) {
        const bool white = image->buf[(offset + row) * image->stride + offset + col] != 0;
        ASSERT_EQ(family->Bit(code, row, col), white)
            << name << " ID " << id << " cell (" << row << ", " << col << ")";
      }
    }
    image_u8_destroy(image);
  }
}

TEST(TagFamilyTest, EveryPayloadEqualsLibapriltagRendering16h5) {
  apriltag_family_t* april = tag16h5_create();
  ExpectMatchesAprilTagRendering("16h5", april);
  tag16h5_destroy(april);
}

TEST(TagFamilyTest, EveryPayloadEqualsLibapriltagRendering36h11) {
  apriltag_family_t* april = tag36h11_create();
  ExpectMatchesAprilTagRendering("36h11", april);
  tag36h11_destroy(april);
}

TEST(TagFamilyTest, KeptCodesHoldBothShadesOfEachColour) {
  for (const auto& name : TagFamily::Names()) {
    auto family = MustLoad(name);
    const int d = family->payload_width();
    for (int id : family->kept_ids()) {
      std::set<bool> red, green;
      for (int row = 0; row < d; ++row) {
        for (int col = 0; col < d; ++col) {
          auto& set = family->CellColorAt(row, col) == CellColor::kRed ? red : green;
          set.insert(family->Bit(family->CodeOf(id), row, col));
        }
      }
      EXPECT_EQ(red.size(), 2u) << name << " " << id;
      EXPECT_EQ(green.size(), 2u) << name << " " << id;
    }
  }
}

TEST(TagFamilyTest, RotationTurnsClockwise) {
  auto family = MustLoad("16h5");
  // Only the top-left cell set: after a clockwise quarter turn it is top-right.
  const Code top_left = Code{1} << 15;
  const Code top_right = Code{1} << 12;
  const Code bottom_right = Code{1};
  EXPECT_EQ(family->Rotate(top_left, 1), top_right);
  EXPECT_EQ(family->Rotate(top_left, 2), bottom_right);
  EXPECT_EQ(family->Rotate(top_left, -1), Code{1} << 3);  // Bottom-left.
  for (int id : family->kept_ids()) {
    const Code code = family->CodeOf(id);
    EXPECT_EQ(family->Rotate(code, 4), code);
    EXPECT_EQ(family->Rotate(family->Rotate(code, 1), 3), code);
  }
}

TEST(TagFamilyTest, MinimumHammingMatchesBruteForceAndAllowsARadius) {
  for (const auto& name : TagFamily::Names()) {
    auto family = MustLoad(name);
    int brute = 64;
    const auto& ids = family->kept_ids();
    for (int a : ids) {
      for (int b : ids) {
        for (int turns = 0; turns < 4; ++turns) {
          if (a == b && turns == 0) continue;
          brute = std::min(
              brute, HammingDistance(family->CodeOf(a), family->Rotate(family->CodeOf(b), turns)));
        }
      }
    }
    EXPECT_EQ(family->min_hamming(), brute) << name;
    EXPECT_GE(family->min_hamming(), family->apriltag_min_hamming()) << name;
    EXPECT_LT(2 * family->max_safe_radius(), family->min_hamming());
    EXPECT_GE(family->max_safe_radius(), 2) << name;
  }
}

TEST(TagFamilyTest, ExplainsInvalidIds) {
  auto family = MustLoad("16h5");
  std::string why;
  EXPECT_TRUE(family->IsValidId(0, &why));
  EXPECT_FALSE(family->IsValidId(5, &why));
  EXPECT_NE(why.find("16h5 ID 5 is rejected"), std::string::npos) << why;
  EXPECT_FALSE(family->IsValidId(30, &why));
  EXPECT_NE(why.find("0-29"), std::string::npos) << why;
  EXPECT_FALSE(family->IsValidId(-1, &why));
}

TEST(TagFamilyTest, AcceptsAprilTagNamesAndRefusesOthers) {
  EXPECT_EQ(MustLoad("tag36h11")->name(), "36h11");
  std::string error;
  EXPECT_EQ(TagFamily::Load("25h9", &error), nullptr);
  EXPECT_EQ(error, "unknown tag family '25h9' (valid: 16h5, 36h11)");
}

}  // namespace
}  // namespace chromatag
