// A candidate's own light: the white of its quiet zone, as the ring scans
// found it, and the colours of the candidate judged against it (von Kries:
// each channel's linear light over the white's), so that a colour cast from
// a wrong white balance and the light level move them little. Internal to
// the detector.
#ifndef CHROMATAG_DETECTOR_SRC_TAG_LIGHT_H_
#define CHROMATAG_DETECTOR_SRC_TAG_LIGHT_H_

#include <array>
#include <cstdint>

#include <opencv2/core.hpp>

#include "image_view.h"
#include "kernels/color_table.h"

namespace chromatag::internal {

class TagLight {
 public:
  // Adds the mean of the 3 x 3 pixels around `at` (clipped to the frame) as
  // one reading of the white.
  void AddWhite(const ImageView& image, cv::Point at);
  int num_whites() const { return num_whites_; }
  // Fixes the white from the readings added: per channel, their median.
  // False when there is none, or the white is too dark to divide by.
  bool Settle();
  bool settled() const { return settled_; }

  // CIELAB of an 8-bit colour seen in the candidate's light: each channel's
  // linear light over the white's, times paper white's (kPaperWhiteY), as if
  // the tag were lit by daylight at the exposure that puts its white at
  // paper white. Settle() first.
  LabF Balanced(const ColorTable& table, uint8_t r, uint8_t g, uint8_t b) const {
    return table.Lab(r, g, b, gain_);
  }
  // The same for the mean of the 3 x 3 pixels around `at`.
  LabF BalancedAt(const ImageView& image, cv::Point at) const;

  // Paper white's relative luminance: L* 95 (the benchmark's prints, and
  // the paper's measured white after the print's own tint).
  static constexpr double kPaperWhiteY = 0.8792;

 private:
  static constexpr int kMaxWhites = 16;
  std::array<std::array<float, kMaxWhites>, 3> whites_{};  // Linear R, G, B.
  int num_whites_ = 0;
  std::array<float, 3> gain_{1, 1, 1};
  bool settled_ = false;
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_TAG_LIGHT_H_
