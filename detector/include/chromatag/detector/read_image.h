// Reading a photo or a frame from a file, the way the CLI reads them: only
// regular files, the size its header claims checked against a budget before
// anything is decoded, and one message that says what was wrong.
#ifndef CHROMATAG_DETECTOR_READ_IMAGE_H_
#define CHROMATAG_DETECTOR_READ_IMAGE_H_

#include <string>

#include <opencv2/core.hpp>

namespace chromatag {

// The image at `path` as 8-bit BGR (OpenCV's order, PixelOrder::kBgr), grey
// and 16-bit files converted; any format OpenCV reads (PNG, JPEG, TIFF, BMP,
// WebP, PPM, PGM). An empty Mat and *error when the file is missing, is not
// a regular file (a FIFO or a device would block), claims more than
// kMaxImagePixels (chromatag/families/input_file.h), or cannot be decoded;
// a PDF or SVG sheet is named as such (chromatag verify reads those).
cv::Mat ReadImage(const std::string& path, std::string* error);

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_READ_IMAGE_H_
