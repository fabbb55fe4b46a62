#include "chromatag/calib/calib_sheet.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "chromatag/detector/detector.h"
#include "chromatag/layout/calib_sheet_layout.h"

namespace chromatag {
namespace {

CalibSheetOptions DefaultOptions() {
  CalibSheetOptions options;
  options.palette = *BuiltinPalette("default");
  return options;
}

TEST(CalibSheetTest, A4LayoutHoldsEveryKindWithoutOverlap) {
  std::string error;
  const auto layout = LayoutCalibSheet(DefaultOptions(), &error);
  ASSERT_TRUE(layout) << error;
  std::map<PatchKind, int> kinds;
  std::map<Shade, int> palette_shades, candidate_colours;
  std::set<std::pair<int, int>> slots;
  for (const Patch& p : layout->patches) {
    ++kinds[p.kind];
    if (p.kind == PatchKind::kPalette) ++palette_shades[p.shade];
    if (p.kind == PatchKind::kCandidate) ++candidate_colours[p.shade];
    EXPECT_TRUE(slots.insert({p.row, p.col}).second) << "two patches in one slot";
    EXPECT_GE(p.origin_mm[0], 10.0);
    EXPECT_GE(p.origin_mm[1], 10.0);
    EXPECT_LE(p.origin_mm[0] + p.size_mm, 200.0);
    EXPECT_LE(p.origin_mm[1] + p.size_mm, 287.0);
    EXPECT_EQ(p.rgb, LabToSrgb8(p.lab));
    // Clear of every corner tag's black square by at least one tag cell.
    for (const CornerTag& tag : layout->tags) {
      const double cell = layout->tag_size_mm / 6.0;
      const bool apart = p.origin_mm[0] > tag.corners_mm[1][0] + cell ||
                         p.origin_mm[0] + p.size_mm < tag.corners_mm[0][0] - cell ||
                         p.origin_mm[1] > tag.corners_mm[2][1] + cell ||
                         p.origin_mm[1] + p.size_mm < tag.corners_mm[0][1] - cell;
      EXPECT_TRUE(apart) << "patch " << p.index << " touches tag " << tag.id;
    }
  }
  EXPECT_GE(kinds[PatchKind::kPaper], 12);
  EXPECT_EQ(kinds[PatchKind::kGrey], 9);
  EXPECT_GE(kinds[PatchKind::kCandidate], 40);
  for (Shade s : {Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0, Shade::kBlack})
    EXPECT_GE(palette_shades[s], 5) << ShadeName(s);
  EXPECT_GE(candidate_colours[Shade::kRed1], 15);
  EXPECT_GE(candidate_colours[Shade::kGreen1], 15);
  std::set<int> ids;
  for (const CornerTag& tag : layout->tags) ids.insert(tag.id);
  EXPECT_EQ(ids.size(), 4u);
}

TEST(CalibSheetTest, SheetIdFixesTheOrderAndTheCornerTags) {
  CalibSheetOptions options = DefaultOptions();
  options.sheet_id = 4711;
  const auto a = LayoutCalibSheet(options);
  const auto b = LayoutCalibSheet(options);
  options.sheet_id = 4712;
  const auto c = LayoutCalibSheet(options);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->sheet_id, 4711);
  int same_as_b = 0, same_as_c = 0;
  ASSERT_EQ(a->patches.size(), c->patches.size());
  for (size_t i = 0; i < a->patches.size(); ++i) {
    same_as_b += a->patches[i].rgb == b->patches[i].rgb;
    same_as_c += a->patches[i].rgb == c->patches[i].rgb;
  }
  EXPECT_EQ(same_as_b, static_cast<int>(a->patches.size()));
  EXPECT_LT(same_as_c, static_cast<int>(a->patches.size()) / 2);
  bool tags_differ = false;
  for (int k = 0; k < 4; ++k) tags_differ |= a->tags[k].id != c->tags[k].id;
  EXPECT_TRUE(tags_differ);
  // Derived IDs are stable too.
  const auto d1 = LayoutCalibSheet(DefaultOptions());
  const auto d2 = LayoutCalibSheet(DefaultOptions());
  EXPECT_EQ(d1->sheet_id, d2->sheet_id);
}

TEST(CalibSheetTest, SmallPageIsRefusedWithTheRoomNeeded) {
  CalibSheetOptions options = DefaultOptions();
  options.page = {"custom", 80, 80};
  std::string error;
  EXPECT_FALSE(LayoutCalibSheet(options, &error));
  EXPECT_NE(error.find("too small"), std::string::npos) << error;
  EXPECT_NE(error.find("needs at least"), std::string::npos) << error;
}

TEST(CalibSheetTest, SidecarRoundTrips) {
  const auto layout = LayoutCalibSheet(DefaultOptions());
  ASSERT_TRUE(layout);
  const auto files = RenderCalibSheet(*layout, CalibSheetFormat::kPdf, "/tmp/x/calib.pdf");
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[1].path, "/tmp/x/calib.pdf.json");
  EXPECT_EQ(files[0].contents.substr(0, 5), "%PDF-");
  std::string error;
  const auto back = ParseCalibSidecar(files[1].contents, &error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(back->sheet_id, layout->sheet_id);
  ASSERT_EQ(back->patches.size(), layout->patches.size());
  for (size_t i = 0; i < back->patches.size(); ++i) {
    EXPECT_EQ(back->patches[i].rgb, layout->patches[i].rgb);
    EXPECT_EQ(back->patches[i].kind, layout->patches[i].kind);
    EXPECT_NEAR(back->patches[i].origin_mm[0], layout->patches[i].origin_mm[0], 1e-3);
    EXPECT_NEAR(back->patches[i].lab.b, layout->patches[i].lab.b, 1e-4);
  }
  for (int k = 0; k < 4; ++k) EXPECT_EQ(back->tags[k].id, layout->tags[k].id);
  // Same layout, same bytes.
  EXPECT_EQ(RenderCalibSheet(*layout, CalibSheetFormat::kPdf, "/tmp/x/calib.pdf")[0].contents,
            files[0].contents);
}

TEST(CalibSheetTest, SidecarErrorsSayWhatIsWrong) {
  std::string error;
  EXPECT_FALSE(ParseCalibSidecar("{", &error));
  EXPECT_NE(error.find("JSON"), std::string::npos);
  EXPECT_FALSE(ParseCalibSidecar(R"({"schema": "chromatag-layout", "schema_version": 1})", &error));
  EXPECT_NE(error.find("not a calibration sheet"), std::string::npos) << error;
  EXPECT_FALSE(ReadCalibSidecar("/nonexistent/calib.json", &error));
  EXPECT_NE(error.find("/nonexistent/calib.json"), std::string::npos);
  // Hostile values in an otherwise good sidecar.
  const auto layout = LayoutCalibSheet(DefaultOptions());
  ASSERT_TRUE(layout);
  const std::string good =
      RenderCalibSheet(*layout, CalibSheetFormat::kPdf, "/tmp/x/calib.pdf")[1].contents;
  ASSERT_TRUE(ParseCalibSidecar(good, &error)) << error;
  const struct {
    std::string from, to, says;
  } cases[] = {
      {"\"tag_size_mm\": ", "\"tag_size_mm\": -", "\"tag_size_mm\" must be in [10, 60]"},
      {"\"tag_size_mm\": ", "\"tag_size_mm\": 1e308, \"x\": ",
       "\"tag_size_mm\" must be in [10, 60]"},
      {"\"slot\": [\n        0", "\"slot\": [\n        -3", "\"slot\" must be [row, column]"},
      {"\"path\": \"calib.pdf\"", "\"path\": \"../../etc/shadow\"",
       "a file must be named by its base name beside the sidecar, not '../../etc/shadow'"},
  };
  for (const auto& c : cases) {
    std::string bad = good;
    const size_t at = bad.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    bad.replace(at, c.from.size(), c.to);
    EXPECT_FALSE(ParseCalibSidecar(bad, &error)) << c.to;
    EXPECT_NE(error.find(c.says), std::string::npos) << c.to << ": " << error;
  }
}

// The sheet is given as the file or as its sidecar, as verify takes a sheet;
// a sidecar that lists another file, or a sheet changed after it was
// written, is refused, as is a sheet without its sidecar.
TEST(CalibSheetTest, ASheetIsGivenAsItsFileOrItsSidecar) {
  const auto layout = LayoutCalibSheet(DefaultOptions());
  ASSERT_TRUE(layout);
  const std::string dir = ::testing::TempDir() + "calib_sheet_given";
  std::filesystem::create_directories(dir);
  const auto files = RenderCalibSheet(*layout, CalibSheetFormat::kPdf, dir + "/calib.pdf");
  auto write = [](const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
  };
  for (const auto& file : files) write(file.path, file.contents);
  std::string error;
  for (const std::string& given : {dir + "/calib.pdf", dir + "/calib.pdf.json"}) {
    const auto read = ReadCalibSheet(given, &error);
    ASSERT_TRUE(read) << given << ": " << error;
    EXPECT_EQ(read->sheet_id, layout->sheet_id);
  }
  write(dir + "/copy.pdf", files[0].contents);
  EXPECT_FALSE(ReadCalibSheet(dir + "/copy.pdf", &error));
  EXPECT_NE(error.find("copy.pdf.json': no such file"), std::string::npos) << error;
  write(dir + "/copy.pdf.json", files[1].contents);
  EXPECT_FALSE(ReadCalibSheet(dir + "/copy.pdf", &error));
  EXPECT_NE(error.find("does not describe '" + dir + "/copy.pdf' (it lists 'calib.pdf')"),
            std::string::npos)
      << error;
  write(dir + "/calib.pdf", files[0].contents + "\n");
  EXPECT_FALSE(ReadCalibSheet(dir + "/calib.pdf", &error));
  EXPECT_NE(error.find("was changed after it was generated"), std::string::npos) << error;
  // The sidecar alone still reads: it holds everything calibrate needs.
  EXPECT_TRUE(ReadCalibSheet(dir + "/calib.pdf.json", &error)) << error;
  std::filesystem::remove_all(dir);
}

TEST(CalibSheetTest, RasterShowsThePatchesAndTheCornerTags) {
  const auto layout = LayoutCalibSheet(DefaultOptions());
  ASSERT_TRUE(layout);
  const double px_per_mm = 5.0;
  const cv::Mat page = RasterizeCalibPage(*layout, px_per_mm);
  EXPECT_EQ(page.cols, 1050);
  EXPECT_EQ(page.rows, 1485);
  for (const Patch& p : layout->patches) {
    const auto c = p.CenterMm();
    const cv::Vec3b px =
        page.at<cv::Vec3b>(static_cast<int>(c[1] * px_per_mm), static_cast<int>(c[0] * px_per_mm));
    const Rgb8 expected = p.kind == PatchKind::kPaper ? Rgb8{255, 255, 255} : p.rgb;
    EXPECT_EQ(px[2], expected.r);
    EXPECT_EQ(px[1], expected.g);
    EXPECT_EQ(px[0], expected.b);
  }
  auto detector = Detector::Create(DetectorOptions{});
  ASSERT_TRUE(detector);
  const DetectionResult result = detector->Detect(page);
  std::set<int> found;
  for (const Detection& d : result.detections) found.insert(d.id);
  for (const CornerTag& tag : layout->tags) EXPECT_TRUE(found.count(tag.id)) << tag.id;
}

}  // namespace
}  // namespace chromatag
