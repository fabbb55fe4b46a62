// Reading a scan's resolution (ReadImageDpi): PNG pHYs, JFIF, TIFF and EXIF
// in either byte order, whichever comes first, and corrupt EXIF ignored.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "chromatag/verify/print_check.h"
#include "jpeg_segments.h"

namespace chromatag {
namespace {

using testing::ExifApp1;
using testing::IfdEntry;
using testing::JfifApp0;
using testing::JpegWith;
using testing::Resolution;

TEST(ReadImageDpiTest, PngPhysJpegJfifAndTiff) {
  // A PNG header with a pHYs chunk of 11811 pixels per metre (300 dpi).
  std::string png("\x89PNG\r\n\x1a\n", 8);
  auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  png += be32(13) + "IHDR" + std::string(13, '\0') + be32(0);
  png += be32(9) + "pHYs" + be32(11811) + be32(23622) + std::string(1, '\1') + be32(0);
  const auto dpi = ReadImageDpi(png);
  ASSERT_TRUE(dpi);
  EXPECT_NEAR((*dpi)[0], 300.0, 0.01);
  EXPECT_NEAR((*dpi)[1], 600.0, 0.01);
  // Unit 0 (aspect only) and a truncated chunk record no resolution.
  std::string aspect_only = png;
  aspect_only[8 + 25 + 16] = '\0';
  EXPECT_FALSE(ReadImageDpi(aspect_only));
  EXPECT_FALSE(ReadImageDpi(png.substr(0, 40)));
  // A JPEG's JFIF APP0 in dots per centimetre, and OpenCV's own (aspect only).
  std::string jpeg("\xFF\xD8\xFF\xE0\x00\x10JFIF\x00\x01\x02\x02\x00\x76\x00\x76\x00\x00", 20);
  const auto jdpi = ReadImageDpi(jpeg);
  ASSERT_TRUE(jdpi);
  EXPECT_NEAR((*jdpi)[0], 118 * 2.54, 0.01);
  std::vector<uint8_t> encoded;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(255, 255, 255)), encoded);
  EXPECT_FALSE(ReadImageDpi(std::string(encoded.begin(), encoded.end())));
  // TIFF, little-endian, 300 x 600 dpi; big-endian in centimetres.
  const std::string tiff_le(
      "II*\0\x08\0\0\0"                     // Header, IFD at 8.
      "\x03\0"                              // Three entries.
      "\x1a\x01\x05\0\x01\0\0\0\x32\0\0\0"  // XResolution at 50.
      "\x1b\x01\x05\0\x01\0\0\0\x3a\0\0\0"  // YResolution at 58.
      "\x28\x01\x03\0\x01\0\0\0\x02\0\0\0"  // ResolutionUnit inch.
      "\0\0\0\0"                            // No next IFD.
      "\x2c\x01\0\0\x01\0\0\0"              // 300 / 1.
      "\x58\x02\0\0\x01\0\0\0",             // 600 / 1.
      66);
  const auto tdpi = ReadImageDpi(tiff_le);
  ASSERT_TRUE(tdpi);
  EXPECT_DOUBLE_EQ((*tdpi)[0], 300.0);
  EXPECT_DOUBLE_EQ((*tdpi)[1], 600.0);
  const std::string tiff_be(
      "MM\0*\0\0\0\x08"
      "\0\x03"
      "\x01\x1a\0\x05\0\0\0\x01\0\0\0\x32"
      "\x01\x1b\0\x05\0\0\0\x01\0\0\0\x3a"
      "\x01\x28\0\x03\0\0\0\x01\0\x03\0\0"
      "\0\0\0\0"
      "\0\0\0\x76\0\0\0\x01"
      "\0\0\0\x76\0\0\0\x01",
      66);
  const auto bdpi = ReadImageDpi(tiff_be);
  ASSERT_TRUE(bdpi);
  EXPECT_NEAR((*bdpi)[0], 118 * 2.54, 1e-9);
  EXPECT_FALSE(ReadImageDpi(tiff_le.substr(0, 30)));  // Cut inside the IFD.
  EXPECT_FALSE(ReadImageDpi("not an image"));
  EXPECT_FALSE(ReadImageDpi(""));
}

TEST(ReadImageDpiTest, JpegExifInInchesWithoutJfif) {
  // As cameras and most scanners write it: EXIF only. The file still decodes.
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string jpeg = JpegWith(white, "", ExifApp1({Resolution(300, 1, 300, 1, 2)}));
  const cv::Mat raw(1, static_cast<int>(jpeg.size()), CV_8U, const_cast<char*>(jpeg.data()));
  EXPECT_EQ(cv::imdecode(raw, cv::IMREAD_COLOR).size(), white.size());
  const auto dpi = ReadImageDpi(jpeg);
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 300.0);
  EXPECT_DOUBLE_EQ((*dpi)[1], 300.0);
  // Big-endian (Motorola), no ResolutionUnit (inch by default), x and y apart.
  const auto be =
      ReadImageDpi(JpegWith(white, "", ExifApp1({Resolution(600, 2, 1200, 2, 0)}, false)));
  ASSERT_TRUE(be);
  EXPECT_DOUBLE_EQ((*be)[0], 300.0);
  EXPECT_DOUBLE_EQ((*be)[1], 600.0);
}

TEST(ReadImageDpiTest, JpegExifInCentimetres) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto dpi =
      ReadImageDpi(JpegWith(white, "", ExifApp1({Resolution(11811, 100, 11811, 100, 3)})));
  ASSERT_TRUE(dpi);
  EXPECT_NEAR((*dpi)[0], 300.0, 0.01);
  EXPECT_NEAR((*dpi)[1], 300.0, 0.01);
}

TEST(ReadImageDpiTest, JpegExifBeforeJfif) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string exif600 = ExifApp1({Resolution(600, 1, 600, 1, 2)});
  // JFIF aspect only (units 0, as OpenCV and many cameras write) and EXIF 600.
  auto dpi = ReadImageDpi(JpegWith(white, JfifApp0(0, 1, 1), exif600));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 600.0);
  // Both record one and they differ: EXIF's, the device's, over JFIF's default.
  dpi = ReadImageDpi(JpegWith(white, JfifApp0(1, 72, 72), exif600));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 600.0);
  // EXIF without a resolution, or with one in no unit (1): JFIF's.
  const std::vector<IfdEntry> orientation{{274, 3, 1, 0}};
  for (const std::string& exif :
       {ExifApp1({orientation}), ExifApp1({Resolution(600, 1, 600, 1, 1)}),
        ExifApp1({Resolution(600, 0, 600, 0, 2)})}) {
    dpi = ReadImageDpi(JpegWith(white, JfifApp0(2, 118, 118), exif));
    ASSERT_TRUE(dpi);
    EXPECT_NEAR((*dpi)[0], 118 * 2.54, 1e-9);
  }
  // JFIF alone.
  dpi = ReadImageDpi(JpegWith(white, JfifApp0(1, 200, 100), ""));
  ASSERT_TRUE(dpi);
  EXPECT_DOUBLE_EQ((*dpi)[0], 200.0);
  EXPECT_DOUBLE_EQ((*dpi)[1], 100.0);
}

TEST(ReadImageDpiTest, JpegWithoutResolution) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", "")));
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, JfifApp0(0, 1, 1), "")));
  // EXIF with no resolution in IFD0 records none: not libexif's default of
  // 72 dpi, nor the thumbnail's (IFD1).
  const std::vector<IfdEntry> unit_only{{296, 3, 2, 0}};
  EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", ExifApp1({unit_only}))));
  EXPECT_FALSE(ReadImageDpi(
      JpegWith(white, JfifApp0(0, 1, 1), ExifApp1({unit_only, Resolution(72, 1, 72, 1, 2)}))));
}

TEST(ReadImageDpiTest, JpegCorruptExifIsIgnored) {
  const cv::Mat white(8, 8, CV_8UC3, cv::Scalar(255, 255, 255));
  const std::string jfif = JfifApp0(1, 300, 300), exif = ExifApp1({Resolution(600, 1, 600, 1, 2)});
  auto dpi_x = [](const std::string& jpeg) {
    const auto dpi = ReadImageDpi(jpeg);
    return dpi ? (*dpi)[0] : 0.0;
  };
  ASSERT_EQ(dpi_x(JpegWith(white, jfif, exif)), 600.0);
  // The segment's header and nothing usable after it; IFD0 beyond the
  // block; the rationals beyond it; the segment longer than the file.
  std::string no_tiff = exif.substr(0, 10) + "garbage";
  no_tiff[3] = static_cast<char>(no_tiff.size() - 2);
  std::string far_ifd = exif, far_values = exif;
  far_ifd[14] = '\x7F';                 // IFD0's offset, little-endian, low byte.
  far_values[10 + 8 + 2 + 8] = '\xF0';  // XResolution's value offset.
  far_values[10 + 8 + 2 + 12 + 8] = '\xF0';
  for (const std::string& bad : {no_tiff, far_ifd, far_values}) {
    EXPECT_EQ(dpi_x(JpegWith(white, jfif, bad)), 300.0);
    EXPECT_FALSE(ReadImageDpi(JpegWith(white, "", bad)));
  }
  const std::string whole = JpegWith(white, jfif, exif);
  std::string long_segment = whole.substr(0, 20 + exif.size());
  long_segment[20 + 3] = '\x7F';  // Claims more than the file holds.
  EXPECT_EQ(dpi_x(long_segment), 300.0);
  // Cut anywhere, or any byte of the EXIF block broken: JFIF's, EXIF's or
  // none, never a crash.
  for (size_t size = 0; size <= whole.size(); ++size) {
    const double x = dpi_x(whole.substr(0, size));
    EXPECT_TRUE(x == 0.0 || x == 300.0 || x == 600.0) << size << ": " << x;
  }
  for (size_t i = 24; i < 20 + exif.size(); ++i) {
    for (char c : {'\x00', '\xFF'}) {
      std::string broken = whole;
      broken[i] = c;
      const auto dpi = ReadImageDpi(broken);
      EXPECT_TRUE(!dpi || (std::isfinite((*dpi)[0]) && (*dpi)[0] > 0)) << i;
    }
  }
}

}  // namespace
}  // namespace chromatag
