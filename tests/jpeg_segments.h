// JPEG segments written by hand for the tests of reading an image's
// resolution: EXIF in either byte order with chained IFDs, JFIF densities,
// and a JPEG carrying them in place of OpenCV's own APP0.
#ifndef CHROMATAG_TESTS_JPEG_SEGMENTS_H_
#define CHROMATAG_TESTS_JPEG_SEGMENTS_H_

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace chromatag::testing {

// One IFD entry of an EXIF block, one value: a RATIONAL (type 5) a / b or a
// SHORT (type 3) a.
struct IfdEntry {
  uint16_t tag, type;
  uint32_t a, b;
};

// IFD0's resolution entries: XResolution, YResolution and, unless 0,
// ResolutionUnit.
inline std::vector<IfdEntry> Resolution(uint32_t x_num, uint32_t x_den, uint32_t y_num,
                                        uint32_t y_den, uint32_t unit) {
  std::vector<IfdEntry> entries{{282, 5, x_num, x_den}, {283, 5, y_num, y_den}};
  if (unit) entries.push_back({296, 3, unit, 0});
  return entries;
}

// A JPEG APP1 segment holding EXIF as cameras write it: "Exif\0\0", a TIFF
// header in either byte order, the IFDs chained (IFD0 first, then IFD1, the
// thumbnail's), the rationals after them.
inline std::string ExifApp1(const std::vector<std::vector<IfdEntry>>& ifds, bool little = true) {
  auto u16 = [little](uint32_t v) {
    const char lo = static_cast<char>(v), hi = static_cast<char>(v >> 8);
    return little ? std::string{lo, hi} : std::string{hi, lo};
  };
  auto u32 = [&](uint32_t v) {
    return little ? u16(v & 0xFFFF) + u16(v >> 16) : u16(v >> 16) + u16(v & 0xFFFF);
  };
  uint32_t data_at = 8;
  for (const auto& ifd : ifds) data_at += 2 + 12 * static_cast<uint32_t>(ifd.size()) + 4;
  std::string tiff = std::string(little ? "II" : "MM") + u16(42) + u32(8), data;
  uint32_t next = 8;
  for (size_t i = 0; i < ifds.size(); ++i) {
    tiff += u16(static_cast<uint32_t>(ifds[i].size()));
    for (const IfdEntry& e : ifds[i]) {
      tiff += u16(e.tag) + u16(e.type) + u32(1);
      if (e.type == 5) {
        tiff += u32(data_at + static_cast<uint32_t>(data.size()));
        data += u32(e.a) + u32(e.b);
      } else {
        tiff += u16(e.a) + u16(0);
      }
    }
    next += 2 + 12 * static_cast<uint32_t>(ifds[i].size()) + 4;
    tiff += u32(i + 1 < ifds.size() ? next : 0);
  }
  const std::string payload = std::string("Exif\0\0", 6) + tiff + data;
  const size_t length = payload.size() + 2;
  return std::string("\xFF\xE1", 2) + static_cast<char>(length >> 8) +
         static_cast<char>(length & 0xFF) + payload;
}

// A JFIF APP0 segment: density x by y in `units` (0 aspect only, 1 dots per
// inch, 2 per centimetre).
inline std::string JfifApp0(int units, int x, int y) {
  std::string app0("\xFF\xE0\x00\x10JFIF\x00\x01\x01", 11);
  for (int v : {units, x >> 8, x & 0xFF, y >> 8, y & 0xFF, 0, 0}) app0 += static_cast<char>(v);
  return app0;
}

// `image` as a JPEG whose segments before OpenCV's tables are `app0` then
// `app1` (either "" for none), in place of OpenCV's JFIF APP0.
inline std::string JpegWith(const cv::Mat& image, const std::string& app0,
                            const std::string& app1) {
  std::vector<uint8_t> encoded;
  cv::imencode(".jpg", image, encoded, {cv::IMWRITE_JPEG_QUALITY, 95});
  const std::string jpeg(encoded.begin(), encoded.end());
  EXPECT_EQ(jpeg.compare(0, 4, "\xFF\xD8\xFF\xE0", 4), 0);
  const size_t app0_end =
      4 + (static_cast<unsigned char>(jpeg[4]) << 8 | static_cast<unsigned char>(jpeg[5]));
  return jpeg.substr(0, 2) + app0 + app1 + jpeg.substr(app0_end);
}

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_JPEG_SEGMENTS_H_
