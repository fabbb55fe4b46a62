#include "chromatag/generator/id_list.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

TEST(IdListTest, ParsesIdsAndRanges) {
  auto family = TagFamily::Load("36h11");
  const auto ids = ParseIdList("0-3, 12,20-21", *family);
  ASSERT_TRUE(ids);
  EXPECT_EQ(*ids, (std::vector<int>{0, 1, 2, 3, 12, 20, 21}));
  EXPECT_EQ(FormatIdRanges(*ids), "0-3, 12, 20-21");
}

TEST(IdListTest, NamesRejectedAndOutOfRangeIds) {
  auto family = TagFamily::Load("16h5");
  std::string error;
  EXPECT_FALSE(ParseIdList("0-9", *family, &error));
  EXPECT_EQ(error, "16h5 ID 5 is rejected: red cells are all bit 1 (one shade, cannot be split)");
  EXPECT_FALSE(ParseIdList("31", *family, &error));
  EXPECT_NE(error.find("outside 16h5 (IDs 0-29)"), std::string::npos) << error;
  EXPECT_FALSE(ParseIdList("3-1", *family, &error));
  EXPECT_NE(error.find("backwards"), std::string::npos);
  EXPECT_FALSE(ParseIdList("1,1", *family, &error));
  EXPECT_NE(error.find("twice"), std::string::npos);
  EXPECT_FALSE(ParseIdList("a", *family, &error));
  EXPECT_NE(error.find("expected IDs and ranges"), std::string::npos);
  EXPECT_FALSE(ParseIdList("", *family, &error));
}

}  // namespace
}  // namespace chromatag
