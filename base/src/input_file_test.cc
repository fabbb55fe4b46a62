#include "chromatag/base/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <vector>

namespace chromatag {
namespace {

TEST(InputFileTest, OnlyRegularFilesUnderTheCap) {
  std::string error;
  EXPECT_FALSE(ReadInputFile("/dev/zero", "palette file", 100, &error));
  EXPECT_EQ(error, "cannot read palette file '/dev/zero': not a regular file");
  EXPECT_FALSE(ReadInputFile("/tmp", "sidecar", 100, &error));
  EXPECT_EQ(error, "cannot read sidecar '/tmp': not a regular file");
  EXPECT_FALSE(ReadInputFile("/nonexistent/x", "sidecar", 100, &error));
  EXPECT_EQ(error, "cannot read sidecar '/nonexistent/x': no such file");
  const std::string fifo = ::testing::TempDir() + "/input_file_fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(ReadInputFile(fifo, "detector config", 100, &error));  // Would block if opened.
  EXPECT_NE(error.find("not a regular file"), std::string::npos);
  std::remove(fifo.c_str());
  const std::string path = ::testing::TempDir() + "/input_file.txt";
  std::ofstream(path) << "0123456789";
  EXPECT_EQ(ReadInputFile(path, "x", 10, &error).value_or(""), "0123456789");
  EXPECT_FALSE(ReadInputFile(path, "x", 9, &error));
  EXPECT_NE(error.find("10 bytes, over the limit of 9"), std::string::npos) << error;
}

TEST(InputFileTest, JsonDepthIgnoresBracketsInStrings) {
  EXPECT_FALSE(JsonDeeperThan(R"({"a": [[1, 2], {"b": "[[[[[[["}]})", 3));
  EXPECT_TRUE(JsonDeeperThan(R"({"a": [[[1]]]})", 3));
  EXPECT_FALSE(JsonDeeperThan(R"({"a": "\"[[[[[["})", 1));
  EXPECT_TRUE(JsonDeeperThan(std::string(100000, '[') + std::string(100000, ']'), kMaxJsonDepth));
}

TEST(InputFileTest, Utf8) {
  EXPECT_TRUE(IsValidUtf8("tags.pdf"));
  EXPECT_TRUE(IsValidUtf8("\xc3\xa9t\xc3\xa9.pdf"));  // été
  EXPECT_TRUE(IsValidUtf8("\xf0\x9f\x98\x80"));       // U+1F600
  EXPECT_FALSE(IsValidUtf8("bad\xff.pdf"));
  EXPECT_FALSE(IsValidUtf8("\xc3"));          // Cut short.
  EXPECT_FALSE(IsValidUtf8("\xc0\xaf"));      // Overlong '/'.
  EXPECT_FALSE(IsValidUtf8("\xed\xa0\x80"));  // A surrogate.
}

std::string Encode(const std::string& ext, const cv::Mat& image) {
  std::vector<uchar> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes)) << ext;
  return std::string(bytes.begin(), bytes.end());
}

ImageSize SizeOf(const std::string& bytes, bool* ok) {
  ImageSize size;
  *ok = ImageBytesSize(bytes, &size);
  return size;
}

// Every format OpenCV writes here is sized from its header alone, as the
// file itself and as bytes in memory.
TEST(ImageHeaderSizeTest, ReadsEveryFormatsHeader) {
  const cv::Mat colour(37, 53, CV_8UC3, cv::Scalar(10, 200, 30));
  const cv::Mat grey(37, 53, CV_8UC1, cv::Scalar(90));
  const std::vector<std::pair<std::string, cv::Mat>> cases = {
      {".png", colour}, {".jpg", colour}, {".tif", colour}, {".bmp", colour}, {".webp", colour},
      {".ppm", colour}, {".pgm", grey},   {".pbm", grey},   {".pam", colour}};
  for (const auto& [ext, image] : cases) {
    bool ok = false;
    const std::string bytes = Encode(ext, image);
    const ImageSize size = SizeOf(bytes, &ok);
    ASSERT_TRUE(ok) << ext;
    EXPECT_EQ(size.width, 53u) << ext;
    EXPECT_EQ(size.height, 37u) << ext;
    const std::string path = ::testing::TempDir() + "/header_size" + ext;
    std::ofstream(path, std::ios::binary) << bytes;
    ImageSize from_file;
    ASSERT_TRUE(ImageHeaderSize(path, &from_file)) << ext;
    EXPECT_EQ(from_file.width, 53u) << ext;
    EXPECT_EQ(from_file.height, 37u) << ext;
    std::remove(path.c_str());
  }
  // WebP lossless (VP8L, OpenCV's quality above 100) as well as lossy (VP8).
  std::vector<uchar> vp8l;
  ASSERT_TRUE(cv::imencode(".webp", colour, vp8l, {cv::IMWRITE_WEBP_QUALITY, 101}));
  ASSERT_EQ(std::string(vp8l.begin() + 12, vp8l.begin() + 16), "VP8L");
  bool ok = false;
  const ImageSize lossless = SizeOf(std::string(vp8l.begin(), vp8l.end()), &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(lossless.width, 53u);
  EXPECT_EQ(lossless.height, 37u);
}

// Headers that claim a bomb's size are read where OpenCV would read them:
// a JPEG whose frame follows fill bytes and thousands of markers, a tiny
// TIFF or BigTIFF claiming 30000 x 30000, a top-down BMP.
TEST(ImageHeaderSizeTest, FindsTheSizeWhereDecodersDo) {
  std::string jpeg = "\xff\xd8";
  for (int i = 0; i < 3000; ++i) jpeg += std::string("\xff\xfe\x00\x04xy", 6);  // Comments.
  jpeg += std::string("\xff\xff\xff\xc0\x00\x11\x08\x75\x30\x75\x30", 11);      // Fill bytes, SOF0.
  bool ok = false;
  ImageSize size = SizeOf(jpeg, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  EXPECT_EQ(size.height, 30000u);
  EXPECT_NE(ImageSizeProblem(size).find("30000 x 30000 pixels, over the limit of 256 Mpx"),
            std::string::npos);

  // Little-endian TIFF: IFD at 8, two LONG entries.
  std::string tiff("II*\0\x08\0\0\0\x02\0", 10);
  tiff += std::string("\x00\x01\x04\x00\x01\x00\x00\x00\x30\x75\x00\x00", 12);  // 256 = 30000
  tiff += std::string("\x01\x01\x03\x00\x01\x00\x00\x00\x30\x75\x00\x00", 12);  // 257 = 30000
  size = SizeOf(tiff, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  EXPECT_EQ(size.height, 30000u);
  // Big-endian BigTIFF: version 43, 8-byte offsets, 20-byte entries.
  std::string big("MM\0\x2b\0\x08\0\0", 8);
  big += std::string("\0\0\0\0\0\0\0\x10", 8);  // The first IFD at 16.
  big += std::string("\0\0\0\0\0\0\0\x02", 8);
  big += std::string("\x01\x00\x00\x10\0\0\0\0\0\0\0\x01\0\0\0\0\0\0\x75\x30", 20);
  big += std::string("\x01\x01\x00\x03\0\0\0\0\0\0\0\x01\x4e\x20\0\0\0\0\0\0", 20);
  size = SizeOf(big, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  EXPECT_EQ(size.height, 20000u);

  // BMP with a negative (top-down) height.
  std::string bmp("BM\0\0\0\0\0\0\0\0\x36\0\0\0\x28\0\0\0", 18);
  bmp += std::string("\x10\x27\0\0\xf0\xd8\xff\xff", 8);  // 10000 x -10000
  size = SizeOf(bmp, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 10000u);
  EXPECT_EQ(size.height, 10000u);

  const std::string pnm = "P6\n# a comment\n 640\n# another\n480\n255\n";
  size = SizeOf(pnm, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 640u);
  EXPECT_EQ(size.height, 480u);
  EXPECT_EQ(ImageSizeProblem(size), "");
}

// Headers crafted so that a looser reader would find a small size where the
// decoder finds a bomb: each is sized as the decoder sizes it.
TEST(ImageHeaderSizeTest, ReadsAsTheDecodersRead) {
  bool ok = false;
  // libjpeg takes FF 00 as stray data and scans on to the real frame; a fake
  // 1 x 1 frame hides in a comment after it.
  std::string jpeg("\xff\xd8\xff\x00\x00\x19", 6);
  jpeg += std::string("\xff\xc0\x00\x11\x08\x75\x30\x75\x30", 9) + std::string(12, '\0');
  jpeg += std::string("\xff\xfe\x00\x0b\xff\xc0\x00\x11\x08\x00\x01\x00\x01", 13);
  ImageSize size = SizeOf(jpeg, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  // Stray bytes between markers (some cameras write them) are skipped too
  // (right after SOI they are not: OpenCV wants FF D8 FF to call it JPEG).
  const std::string stray = std::string("\xff\xd8\xff\xfe\x00\x04xy\x12\x34", 10) + jpeg.substr(2);
  size = SizeOf(stray, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.height, 30000u);
  // TIFF: the first ImageWidth counts (libtiff's), whatever its integer type.
  std::string tiff("II*\0\x08\0\0\0\x03\0", 10);
  tiff += std::string("\x00\x01\x09\x00\x01\x00\x00\x00\x30\x75\x00\x00", 12);  // SLONG
  tiff += std::string("\x00\x01\x03\x00\x01\x00\x00\x00\x01\x00\x00\x00", 12);  // SHORT 1
  tiff += std::string("\x01\x01\x03\x00\x01\x00\x00\x00\x30\x75\x00\x00", 12);
  size = SizeOf(tiff, &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  // A width of a type that holds no size (ASCII) is refused.
  std::string ascii = tiff;
  ascii[12] = '\x02';
  SizeOf(ascii, &ok);
  EXPECT_FALSE(ok);
  // PNM: a comment ends at \r as well (OpenCV's reader).
  size = SizeOf("P6\n#\r30000 30000\n1 1\n255\n", &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  // PAM: the header's own lines (a tab after the keyword), not words in the
  // pixel data after ENDHDR.
  size = SizeOf(
      "P7\n WIDTH\t30000\nHEIGHT 30000\nDEPTH 3\nMAXVAL 255\nENDHDR\n\nWIDTH 1\nHEIGHT 1\n", &ok);
  ASSERT_TRUE(ok);
  EXPECT_EQ(size.width, 30000u);
  EXPECT_EQ(size.height, 30000u);
  SizeOf("P7\nWIDTH 5\nWIDTH 1\nHEIGHT 1\nENDHDR\n", &ok);
  EXPECT_FALSE(ok);  // Twice: refused.
}

// What cannot be sized from a header is not sized: other formats, cut
// headers, a JPEG scan before any frame, a size of 0.
TEST(ImageHeaderSizeTest, RefusesWhatItCannotSize) {
  const std::string png = Encode(".png", cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(0)));
  const std::string jpeg = Encode(".jpg", cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(0)));
  bool ok = true;
  for (const std::string& bytes :
       {std::string(), std::string("GIF89a\x10\0\x10\0", 10), std::string("%PDF-1.5\n"),
        png.substr(0, 20), jpeg.substr(0, 6), std::string("\xff\xd8\xff\xda\x00\x02", 6),
        std::string("II*\0\xff\xff\xff\x00", 8), std::string("P6\n640"),
        std::string("RIFF\0\0\0\0WEBPVP8Z", 16)}) {
    SizeOf(bytes, &ok);
    EXPECT_FALSE(ok) << bytes.size() << " bytes";
  }
  ImageSize zero;
  zero.width = 0;
  zero.height = 10;
  EXPECT_EQ(ImageSizeProblem(zero), "its header gives a size of 0");
  ImageSize wide;
  wide.width = uint64_t{1} << 33;
  wide.height = 1;
  EXPECT_NE(ImageSizeProblem(wide), "");
  ImageSize ok_size;
  EXPECT_FALSE(ImageHeaderSize("/nonexistent/x.png", &ok_size));
}

}  // namespace
}  // namespace chromatag
