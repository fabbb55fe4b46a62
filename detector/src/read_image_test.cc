#include "chromatag/detector/read_image.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

namespace chromatag {
namespace {

namespace fs = std::filesystem;

class ReadImageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("chromatag_read_image_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// Colour, grey and 16-bit files all come back as 8-bit BGR with their pixels.
TEST_F(ReadImageTest, ReadsFilesAsEightBitBgr) {
  cv::Mat bgr(7, 9, CV_8UC3, cv::Scalar(10, 120, 230));
  ASSERT_TRUE(cv::imwrite(Path("colour.png"), bgr));
  cv::Mat grey(5, 4, CV_8UC1, cv::Scalar(77));
  ASSERT_TRUE(cv::imwrite(Path("grey.png"), grey));
  cv::Mat deep(3, 3, CV_16UC3, cv::Scalar(256 * 40, 256 * 50, 256 * 60));
  ASSERT_TRUE(cv::imwrite(Path("deep.png"), deep));

  std::string error;
  const cv::Mat colour = ReadImage(Path("colour.png"), &error);
  ASSERT_EQ(colour.type(), CV_8UC3) << error;
  EXPECT_EQ(colour.size(), bgr.size());
  EXPECT_EQ(colour.at<cv::Vec3b>(3, 4), cv::Vec3b(10, 120, 230));
  const cv::Mat from_grey = ReadImage(Path("grey.png"), &error);
  ASSERT_EQ(from_grey.type(), CV_8UC3);
  EXPECT_EQ(from_grey.at<cv::Vec3b>(1, 1), cv::Vec3b(77, 77, 77));
  const cv::Mat from_deep = ReadImage(Path("deep.png"), &error);
  ASSERT_EQ(from_deep.type(), CV_8UC3);
  EXPECT_EQ(from_deep.at<cv::Vec3b>(0, 0), cv::Vec3b(40, 50, 60));
}

// Each way a file can be unreadable is an empty Mat and one message naming
// the file and the reason; nothing blocks (a FIFO would, read blindly).
TEST_F(ReadImageTest, SaysWhyAFileCannotBeRead) {
  std::ofstream(Path("notes.png")) << "not an image";
  std::ofstream(Path("cut.png"), std::ios::binary) << std::string("\x89PNG\r\n\x1a\n\0\0", 10);
  std::ofstream(Path("sheet.pdf")) << "%PDF-1.5\n";
  ASSERT_EQ(::mkfifo(Path("pipe.png").c_str(), 0600), 0);
  // A PNG header claiming 40000 x 40000 pixels: refused before decoding.
  std::string huge = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\x0dIHDR", 8);
  for (int s = 24; s >= 0; s -= 8) huge.push_back(static_cast<char>(40000u >> s));
  for (int s = 24; s >= 0; s -= 8) huge.push_back(static_cast<char>(40000u >> s));
  huge += std::string("\x08\x02\0\0\0\0\0\0\0", 9);
  std::ofstream(Path("huge.png"), std::ios::binary) << huge;

  const struct {
    std::string name, says;
  } cases[] = {
      {"missing.png", "': no such file"},
      {"", "': not a regular file"},  // The folder itself.
      {"pipe.png", "': not a regular file"},
      {"notes.png", "': not a PNG, JPEG, TIFF, BMP, WebP, PPM/PGM/PAM/PFM file"},
      {"cut.png", "': its header cannot be read (damaged or cut short)"},
      {"sheet.pdf", "': a PDF or SVG sheet is rasterised and checked by the round trip (verify)"},
      {"huge.png", "': 40000 x 40000 pixels, over the limit of 256 Mpx"},
  };
  for (const auto& c : cases) {
    std::string error;
    const std::string path = Path(c.name);
    EXPECT_TRUE(ReadImage(path, &error).empty()) << c.name;
    EXPECT_EQ(error.rfind("cannot read image '" + path + c.says, 0), 0u) << error;
  }
  // No error pointer: still an empty Mat, no crash.
  EXPECT_TRUE(ReadImage(Path("missing.png"), nullptr).empty());
}

}  // namespace
}  // namespace chromatag
