// Round trips of generated sheets, untouched and tampered with.
#include "chromatag/verify/sheet_check.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "chromatag/generator/sheet.h"

namespace chromatag {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// Writes a sheet of `ids` and returns its path.
std::string Generate(const std::string& name, const std::string& family, std::vector<int> ids,
                     double size_mm, SheetFormat format) {
  SheetOptions options;
  options.family = TagFamily::Load(family);
  options.ids = ids.empty() ? options.family->kept_ids() : ids;
  options.palette = *BuiltinPalette("default");
  options.tag_size_mm = size_mm;
  options.format = format;
  options.dpi = 200.0;
  const std::string path = ::testing::TempDir() + "/" + name;
  std::string error;
  EXPECT_TRUE(WriteSheet(options, path, &error)) << error;
  return path;
}

SheetVerdict MustVerify(const std::string& path) {
  std::string error;
  auto verdict = VerifySheetFile(path, VerifyOptions(), &error);
  EXPECT_TRUE(verdict) << error;
  return verdict.value_or(SheetVerdict{});
}

std::string Problems(const SheetVerdict& verdict) {
  std::string all;
  for (const auto& tag : verdict.tags) {
    if (!tag.passed) all += tag.problem + "\n";
  }
  for (const auto& problem : verdict.file_problems) all += problem + "\n";
  return all;
}

TEST(SheetCheckTest, UntouchedSheetsOfEveryKeptIdOfBothFamiliesPass) {
  for (const auto& [family, size] :
       {std::pair<std::string, double>{"16h5", 30.0}, {"36h11", 20.0}}) {
    const auto verdict =
        MustVerify(Generate("all_" + family + ".pdf", family, {}, size, SheetFormat::kPdf));
    EXPECT_TRUE(verdict.passed) << family << "\n" << Problems(verdict);
    EXPECT_EQ(verdict.tags_passed, static_cast<int>(TagFamily::Load(family)->kept_ids().size()));
    EXPECT_TRUE(verdict.unexpected.empty());
    for (const auto& tag : verdict.tags) EXPECT_LT(tag.position_error_mm, 0.3) << tag.expected.id;
  }
}

TEST(SheetCheckTest, SvgAndPngSheetsPass) {
  for (SheetFormat format : {SheetFormat::kSvg, SheetFormat::kPng}) {
    const std::string name = std::string("formats.") + SheetFormatName(format);
    const auto verdict = MustVerify(Generate(name, "16h5", {0, 1, 2, 3, 4, 6}, 25.0, format));
    EXPECT_TRUE(verdict.passed) << name << "\n" << Problems(verdict);
  }
}

// Paints over part of a PNG sheet.
void Tamper(const std::string& png_path, const std::function<void(cv::Mat&)>& edit) {
  cv::Mat page = cv::imread(png_path, cv::IMREAD_COLOR);
  ASSERT_FALSE(page.empty());
  edit(page);
  ASSERT_TRUE(cv::imwrite(png_path, page));
}

TEST(SheetCheckTest, RecolouredCellFailsNamingTheTag) {
  const std::string path = Generate("recolour.png", "16h5", {0, 1, 2}, 30.0, SheetFormat::kPng);
  const auto record = ReadSidecar(SidecarPath(path));
  ASSERT_TRUE(record);
  // Cell (0, 0) of ID 1, the second tag: paint it in the other green.
  const PlacedTag& tag = record->tags[1];
  const double px_per_mm = 200.0 / 25.4;
  const double cell = 30.0 / 6.0 * px_per_mm;
  const Palette& palette = record->palette;
  const bool bit = record->family->Bit(record->family->CodeOf(1), 0, 0);
  const Rgb8 other = palette.Srgb8(bit ? Shade::kGreen0 : Shade::kGreen1);
  Tamper(path, [&](cv::Mat& page) {
    const cv::Point2d corner = MmToPixel(tag.corners_mm[0], px_per_mm);
    cv::rectangle(page, cv::Rect(cv::Point(corner.x + cell, corner.y + cell), cv::Size(cell, cell)),
                  cv::Scalar(other.b, other.g, other.r), cv::FILLED);
  });
  const auto verdict = MustVerify(path);
  EXPECT_FALSE(verdict.passed);
  EXPECT_TRUE(verdict.tags[0].passed);
  EXPECT_FALSE(verdict.tags[1].passed);
  EXPECT_NE(verdict.tags[1].problem.find("16h5 ID 1 (page 1"), std::string::npos)
      << verdict.tags[1].problem;
  // The detector refuses a code whose clearly coloured cell disagrees with
  // every ID (detector/decode.cc), so the recoloured tag is either rejected
  // or decoded with a corrected bit; both fail the sheet.
  const std::string& problem = verdict.tags[1].problem;
  EXPECT_TRUE(problem.find("not found") != std::string::npos ||
              problem.find("1 bit(s) corrected") != std::string::npos)
      << problem;
  ASSERT_EQ(verdict.file_problems.size(), 1u);
  EXPECT_NE(verdict.file_problems[0].find("was changed after it was generated"), std::string::npos);
}

TEST(SheetCheckTest, RemovedTagFailsNamingTheTag) {
  const std::string path = Generate("removed.png", "16h5", {0, 1, 2}, 30.0, SheetFormat::kPng);
  const auto record = ReadSidecar(SidecarPath(path));
  ASSERT_TRUE(record);
  const PlacedTag& tag = record->tags[2];
  const double px_per_mm = 200.0 / 25.4;
  Tamper(path, [&](cv::Mat& page) {
    cv::rectangle(page, MmToPixel(tag.corners_mm[0], px_per_mm) - cv::Point2d(20, 20),
                  MmToPixel(tag.corners_mm[2], px_per_mm) + cv::Point2d(20, 20),
                  cv::Scalar(255, 255, 255), cv::FILLED);
  });
  const auto verdict = MustVerify(path);
  EXPECT_FALSE(verdict.passed);
  EXPECT_NE(verdict.tags[2].problem.find("16h5 ID 2 (page 1"), std::string::npos);
  EXPECT_NE(verdict.tags[2].problem.find("not found"), std::string::npos);
}

// Rewrites the sidecar through `edit`.
void EditSidecar(const std::string& sheet_path, const std::function<void(nlohmann::json&)>& edit) {
  auto json = nlohmann::json::parse(ReadFile(SidecarPath(sheet_path)));
  edit(json);
  std::ofstream(SidecarPath(sheet_path)) << json.dump(2);
}

TEST(SheetCheckTest, WrongIdInTheSidecarFailsNamingTheTag) {
  const std::string path = Generate("wrong_id.pdf", "16h5", {0, 1, 2}, 30.0, SheetFormat::kPdf);
  EditSidecar(path, [](nlohmann::json& json) { json["tags"][1]["id"] = 7; });
  const auto verdict = MustVerify(path);
  EXPECT_FALSE(verdict.passed);
  EXPECT_EQ(verdict.tags[1].problem.substr(0, 13), "16h5 ID 7 (pa");
  EXPECT_NE(verdict.tags[1].problem.find("decodes as ID 1 where the sidecar says ID 7"),
            std::string::npos)
      << verdict.tags[1].problem;
}

TEST(SheetCheckTest, MovedTagFailsNamingTheTag) {
  const std::string path = Generate("moved.pdf", "16h5", {0, 1, 2}, 30.0, SheetFormat::kPdf);
  EditSidecar(path, [](nlohmann::json& json) {
    auto& tag = json["tags"][0];
    tag["center_mm"][0] = tag["center_mm"][0].get<double>() + 2.0;
    for (auto& corner : tag["corners_mm"]) corner[0] = corner[0].get<double>() + 2.0;
  });
  const auto verdict = MustVerify(path);
  EXPECT_FALSE(verdict.passed);
  EXPECT_NE(verdict.tags[0].problem.find("16h5 ID 0 (page 1"), std::string::npos);
  EXPECT_NE(verdict.tags[0].problem.find("mm from where the sidecar says"), std::string::npos)
      << verdict.tags[0].problem;
  EXPECT_NEAR(verdict.tags[0].position_error_mm, 2.0, 0.3);
  EXPECT_TRUE(verdict.tags[1].passed);
}

TEST(SheetCheckTest, MissingSidecarAndBadOptionsAreErrors) {
  std::string error;
  EXPECT_FALSE(VerifySheetFile("/nonexistent/tags.pdf", VerifyOptions(), &error));
  EXPECT_EQ(error, "cannot read sheet '/nonexistent/tags.pdf': no such file");
  VerifyOptions options;
  options.dpi = 5.0;
  EXPECT_FALSE(VerifySheetFile("/nonexistent/tags.pdf", options, &error));
  EXPECT_NE(error.find("the resolution must be in [50, 1200] dpi"), std::string::npos);
}

}  // namespace
}  // namespace chromatag
