// Reading a photo or a frame from a file, the way the CLI reads them: only
// regular files, the size its header claims checked against a budget before
// anything is decoded, and one message that says what was wrong.
#ifndef CHROMATAG_DETECTOR_READ_IMAGE_H_
#define CHROMATAG_DETECTOR_READ_IMAGE_H_

#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

namespace chromatag {

// The largest image file read (a 1200 dpi A4 scan as PNG is about 60 MiB).
inline constexpr std::uintmax_t kMaxImageFileBytes = std::uintmax_t{512} << 20;

// The image at `path` as 8-bit BGR (OpenCV's order, PixelOrder::kBgr), grey
// and 16-bit files converted. An empty Mat and *error when the file is
// missing, is not a regular file (a FIFO or a device would block), is over
// kMaxImageFileBytes, or fails DecodeImage.
cv::Mat ReadImage(const std::string& path, std::string* error);

// The same for an image file's bytes (`name` for messages). Its size is read
// from its header first (ImageHeaderSize's formats, chromatag/families/
// input_file.h) and nothing else is decoded: another format, a header that
// cannot be read, or a size over kMaxImagePixels is refused before OpenCV
// sees the data; a PDF or SVG sheet is named as such (chromatag verify reads
// those).
cv::Mat DecodeImage(const std::string& bytes, const std::string& name, std::string* error);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_READ_IMAGE_H_
