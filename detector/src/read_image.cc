#include "chromatag/detector/read_image.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "chromatag/families/input_file.h"

namespace chromatag {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

cv::Mat Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return cv::Mat();
}

}  // namespace

cv::Mat ReadImage(const std::string& path, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return Fail(error, "cannot read image '" + path + "': no such file");
  if (!fs::is_regular_file(status)) {
    return Fail(error, "cannot read image '" + path + "': not a regular file");
  }
  // Opened here first: OpenCV would print its own warning for a file it
  // cannot open, and call it undecodable.
  if (std::FILE* file = std::fopen(path.c_str(), "rb")) {
    std::fclose(file);
  } else {
    return Fail(error, "cannot read image '" + path + "': " + std::strerror(errno));
  }
  int width = 0, height = 0;
  if (ImageHeaderSize(path, &width, &height) &&
      static_cast<double>(width) * height > static_cast<double>(kMaxImagePixels)) {
    return Fail(error, "cannot read image '" + path + "': " + std::to_string(width) + " x " +
                           std::to_string(height) + " pixels, over the limit of " +
                           std::to_string(kMaxImagePixels >> 20) + " Mpx");
  }
  // OpenCV's own exceptions (an allocation it cannot make) become the message.
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_COLOR);
  } catch (const cv::Exception& e) {
    return Fail(error, "cannot read image '" + path + "': " + e.msg);
  }
  if (!image.empty()) return image;
  const std::string ext = LowerExtension(path);
  if (ext == ".pdf" || ext == ".svg") {
    return Fail(error, "cannot read image '" + path +
                           "': a PDF or SVG sheet is checked by chromatag verify; images are PNG, "
                           "JPEG, TIFF, BMP, WebP, PPM or PGM");
  }
  return Fail(error,
              "cannot read image '" + path +
                  "': not an image OpenCV can decode (PNG, JPEG, TIFF, BMP, WebP, PPM, PGM)");
}

}  // namespace chromatag
