// Read-only access to a caller's 8-bit 3-channel frame, in either channel
// order, with colour conversions through the ColorTable. Internal.
#ifndef CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_
#define CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "chromatag/detector/color_table.h"
#include "chromatag/detector/detector.h"

namespace chromatag::internal {

// Nearest integer (halves round up), inline: std::lround is a library call,
// and the scans round two coordinates for every pixel they visit.
inline int RoundToInt(float v) {
  const float shifted = v + 0.5f;
  const int truncated = static_cast<int>(shifted);
  return truncated - (shifted < static_cast<float>(truncated) ? 1 : 0);
}
inline int RoundToInt(double v) { return RoundToInt(static_cast<float>(v)); }

// A linear combination of the encoded R, G, B values. Edges are located on
// such channels because blending (antialiasing, blur) is linear in them, so the
// midpoint between two plateaus marks the true edge; L* or a* would not.
struct ChannelWeights {
  float r = 1.f;
  float g = 1.f;
  float b = 1.f;
};
inline constexpr ChannelWeights kGray{1.f, 1.f, 1.f};            // Black/white, green/black.
inline constexpr ChannelWeights kRedMinusGreen{1.f, -1.f, 0.f};  // Red/green.

class ImageView {
 public:
  ImageView(const cv::Mat& image, PixelOrder order, const ColorTable& table)
      : data_(image.data),
        step_(image.step[0]),
        width_(image.cols),
        height_(image.rows),
        r_(order == PixelOrder::kRgb ? 0 : 2),
        b_(order == PixelOrder::kRgb ? 2 : 0),
        table_(&table) {}

  int width() const { return width_; }
  int height() const { return height_; }
  bool Contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  const uint8_t* Pixel(int x, int y) const { return data_ + y * step_ + 3 * x; }
  uint8_t R(const uint8_t* p) const { return p[r_]; }
  uint8_t G(const uint8_t* p) const { return p[1]; }
  uint8_t B(const uint8_t* p) const { return p[b_]; }
  int r_offset() const { return r_; }
  int b_offset() const { return b_; }
  const ColorTable& table() const { return *table_; }

  float A(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->A(p[r_], p[1], p[b_]);
  }
  float L(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->L(p[r_], p[1], p[b_]);
  }
  LabF Lab(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->Lab(p[r_], p[1], p[b_]);
  }
  // Mean a* over the 3x3 block around (x, y), clipped to the frame.
  float MeanA3x3(int x, int y) const {
    float sum = 0.f;
    int n = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (!Contains(x + dx, y + dy)) continue;
        sum += A(x + dx, y + dy);
        ++n;
      }
    }
    return n ? sum / n : 0.f;
  }

  // Bilinear sample of a channel at sub-pixel (x, y) (pixel centres at
  // integers). False outside the frame. Single precision: exact to a
  // thousandth of a pixel on frames up to 8k wide.
  bool Sample(float x, float y, const ChannelWeights& w, float* value) const {
    if (!(x >= 0.f && y >= 0.f)) return false;  // Also rejects NaN.
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    if (x0 + 1 >= width_ || y0 + 1 >= height_) return false;
    const float tx = x - static_cast<float>(x0), ty = y - static_cast<float>(y0);
    const uint8_t* p = Pixel(x0, y0);
    const uint8_t* q = p + step_;
    auto channel = [&](const uint8_t* px) { return w.r * px[r_] + w.g * px[1] + w.b * px[b_]; };
    const float top = channel(p) + (channel(p + 3) - channel(p)) * tx;
    const float bottom = channel(q) + (channel(q + 3) - channel(q)) * tx;
    *value = top + (bottom - top) * ty;
    return true;
  }

 private:
  const uint8_t* data_;
  size_t step_;
  int width_;
  int height_;
  int r_;
  int b_;
  const ColorTable* table_;
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_
