// What the print check's sources (print_check.cc and the files it is split
// into, print_files.cc, print_report.cc) share.
#ifndef CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_
#define CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_

#include <string>

#include <opencv2/core.hpp>

#include "chromatag/layout/sheet_record.h"

namespace chromatag::internal {

// printf into a string (512 bytes at most).
std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Whether the sidecar's tag size and page are ones a check can work with:
// each in (0, 10 m]. Otherwise *why says which is not.
bool SheetIsSane(const SheetRecord& record, std::string* why);

// `text` with every byte of an invalid UTF-8 sequence replaced by '?', for
// Cairo (whose text calls fail on invalid UTF-8).
std::string Utf8OrReplaced(const std::string& text);

// `p` through the homography `h`. Not cv::perspectiveTransform, which
// multiplies by 1 / w (a last bit apart) and maps a point on the horizon
// (|w| below FLT_EPSILON) to (0, 0), a pixel of the image, where this gives
// infinities or NaN that the samplers refuse.
inline cv::Point2d ApplyHomography(const cv::Matx33d& h, const cv::Point2d& p) {
  const cv::Vec3d v = h * cv::Vec3d(p.x, p.y, 1.0);
  return {v[0] / v[2], v[1] / v[2]};
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_
