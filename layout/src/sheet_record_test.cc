#include "chromatag/layout/sheet_record.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

SheetRecord Board() {
  SheetRecord record;
  record.family = TagFamily::Load("16h5");
  record.tag_size_mm = 30.0;
  record.quiet_zone_cells = 2;
  record.palette = *BuiltinPalette("default");
  record.page = {"a4", 210.0, 297.0};
  record.num_pages = 1;
  record.format = SheetFormat::kPdf;
  record.files.push_back({"out/board.pdf", std::string(64, 'a')});
  record.board = BoardGrid{2, 1, 10.0};
  for (int i = 0; i < 2; ++i) {
    PlacedTag tag;
    tag.id = record.family->kept_ids()[i];
    const double x = 20.0 + 40.0 * i, y = 20.0;
    tag.corners_mm = {{{x, y}, {x + 30, y}, {x + 30, y + 30}, {x, y + 30}}};
    tag.center_mm = {x + 15, y + 15};
    record.tags.push_back(tag);
  }
  record.board_origin_mm = {20.0, 50.0};
  return record;
}

// What the generator writes reads back: the tags, the board, the files
// named beside the sidecar and resolved against the folder it is read from.
TEST(SheetRecordTest, WhatIsWrittenReadsBack) {
  const SheetRecord written = Board();
  std::string error;
  const auto read = ParseSidecar(SidecarJson(written), "here/", &error);
  ASSERT_TRUE(read) << error;
  EXPECT_EQ(read->family->name(), "16h5");
  EXPECT_EQ(read->tag_size_mm, 30.0);
  EXPECT_EQ(read->page.width_mm, 210.0);
  ASSERT_EQ(read->files.size(), 1u);
  EXPECT_EQ(read->files[0].path, "here/board.pdf");
  EXPECT_EQ(read->files[0].sha256, written.files[0].sha256);
  ASSERT_EQ(read->tags.size(), 2u);
  EXPECT_EQ(read->tags[1].id, written.tags[1].id);
  EXPECT_EQ(read->tags[1].corners_mm[2], written.tags[1].corners_mm[2]);
  ASSERT_TRUE(read->board);
  EXPECT_EQ(read->board->columns, 2);
  EXPECT_EQ(read->board_origin_mm, written.board_origin_mm);
}

// A board whose origin is not its bottom-left tag's corner is refused, and
// a file named outside the sidecar's folder.
TEST(SheetRecordTest, RefusesABoardOffItsGridAndAFileOutsideItsFolder) {
  SheetRecord moved = Board();
  moved.board_origin_mm = {21.0, 50.0};
  std::string error;
  EXPECT_FALSE(ParseSidecar(SidecarJson(moved), "", &error));
  EXPECT_NE(error.find("origin_mm"), std::string::npos) << error;
  std::string text = SidecarJson(Board());
  text.replace(text.find("\"board.pdf\""), 11, "\"../x.pdf\"");
  EXPECT_FALSE(ParseSidecar(text, "", &error));
  EXPECT_NE(error.find("a file name beside the sidecar"), std::string::npos) << error;
}

}  // namespace
}  // namespace chromatag
