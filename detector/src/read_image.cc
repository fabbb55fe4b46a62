#include "chromatag/detector/read_image.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "chromatag/base/input_file.h"

namespace chromatag {
namespace {

cv::Mat Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return cv::Mat();
}

}  // namespace

cv::Mat ReadImage(const std::string& path, std::string* error) {
  const auto bytes = ReadInputFile(path, "image", kMaxImageFileBytes, error);
  if (!bytes) return cv::Mat();
  return DecodeImage(*bytes, path, error);
}

cv::Mat DecodeImage(const std::string& bytes, const std::string& name, std::string* error) {
  const std::string cannot = "cannot read image '" + name + "': ";
  ImageSize size;
  if (!ImageBytesSize(bytes, &size)) {
    const std::string ext = LowerExtension(name);
    if (ext == ".pdf" || ext == ".svg" || bytes.rfind("%PDF", 0) == 0) {
      return Fail(error, cannot +
                             "a PDF or SVG sheet is rasterised and checked by the round trip "
                             "(verify); images are " +
                             kSizedImageFormats);
    }
    // A PNG, JPEG or TIFF signature whose header then cannot be walked.
    static const std::string kMagic[] = {std::string("\x89PNG\r\n\x1a\n", 8),
                                         std::string("\xff\xd8\xff", 3),
                                         std::string("II*\0", 4),
                                         std::string("MM\0*", 4),
                                         std::string("II+\0", 4),
                                         std::string("MM\0+", 4)};
    for (const std::string& magic : kMagic) {
      if (bytes.compare(0, magic.size(), magic) == 0)
        return Fail(error, cannot + "its header cannot be read (damaged or cut short)");
    }
    return Fail(error, cannot + "not a " + std::string(kSizedImageFormats) +
                           " file (the size is read from the header before decoding)");
  }
  const std::string problem = ImageSizeProblem(size);
  if (!problem.empty()) return Fail(error, cannot + problem);
  // OpenCV's own exceptions (an allocation it cannot make) become the message.
  cv::Mat image;
  try {
    const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data()));
    image = cv::imdecode(raw, cv::IMREAD_COLOR);
  } catch (const cv::Exception& e) {
    return Fail(error, cannot + e.msg);
  }
  if (image.empty())
    return Fail(error, cannot + "its data cannot be decoded (damaged or cut short)");
  return image;
}

}  // namespace chromatag
