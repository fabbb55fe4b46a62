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

  float Channel(int x, int y, const ChannelWeights& w) const {
    const uint8_t* p = Pixel(x, y);
    return w.r * p[r_] + w.g * p[1] + w.b * p[b_];
  }
  // Bilinear sample of a channel at sub-pixel (x, y) (pixel centres at
  // integers). False outside the frame.
  bool Sample(double x, double y, const ChannelWeights& w, float* value) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= width_ || y0 + 1 >= height_) return false;
    const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
    const float top = Channel(x0, y0, w) * (1.f - tx) + Channel(x0 + 1, y0, w) * tx;
    const float bottom = Channel(x0, y0 + 1, w) * (1.f - tx) + Channel(x0 + 1, y0 + 1, w) * tx;
    *value = top * (1.f - ty) + bottom * ty;
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
