// Read-only access to a caller's 8-bit 3-channel frame, in either channel
// order, with colour conversions through the ColorTable and the detector's
// vector kernels (kernels/kernels.h). Internal.
#ifndef CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_
#define CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"
#include "kernels/color_table.h"
#include "kernels/kernels.h"

namespace chromatag::internal {

// Nearest integer (halves round up), inline: std::lround is a library call,
// and the scans round two coordinates for every pixel they visit.
// `v` must lie within +-2^30 (the scans' coordinates do: a start inside the
// frame plus at most a frame's size of steps); no clamp here, where every
// scanned pixel passes (clamping cost 2 us of detector_bench's 51 us).
inline int RoundToInt(float v) {
  const float shifted = v + 0.5f;
  const int truncated = static_cast<int>(shifted);
  return truncated - (shifted < static_cast<float>(truncated) ? 1 : 0);
}
// For coordinates from a homography or a fit, which can be anything: values
// beyond +-2^30 (and NaN, taken as the lower bound) are clamped first, so
// that the casts are defined; such points lie outside any frame.
inline int RoundToInt(double v) {
  constexpr double kLimit = 1073741824.0;
  return RoundToInt(static_cast<float>(v > -kLimit ? (v < kLimit ? v : kLimit) : -kLimit));
}

// A linear combination of the encoded R, G, B values. Edges are located on
// such channels because blending (antialiasing, blur) is linear in them, so the
// midpoint between two plateaus marks the true edge; L* or a* would not.
struct ChannelWeights {
  int r = 1;
  int g = 1;
  int b = 1;
};
inline constexpr ChannelWeights kGray{1, 1, 1};            // Black/white, green/black.
inline constexpr ChannelWeights kRedMinusGreen{1, -1, 0};  // Red/green.

class ImageView {
 public:
  // `kernels`: the detector's (Kernels::ForCpu), or a given path's in tests.
  ImageView(const cv::Mat& image, PixelOrder order, const ColorTable& table,
            const Kernels& kernels = Kernels::ForCpu())
      : data_(image.data),
        step_(image.step[0]),
        width_(image.cols),
        height_(image.rows),
        r_(order == PixelOrder::kRgb ? 0 : 2),
        b_(order == PixelOrder::kRgb ? 2 : 0),
        table_(&table),
        kernels_(&kernels) {}

  int width() const { return width_; }
  int height() const { return height_; }
  bool Contains(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  const uint8_t* Pixel(int x, int y) const { return data_ + y * step_ + 3 * x; }
  uint8_t R(const uint8_t* p) const { return p[r_]; }
  uint8_t G(const uint8_t* p) const { return p[1]; }
  uint8_t B(const uint8_t* p) const { return p[b_]; }
  int r_offset() const { return r_; }
  const uint8_t* data() const { return data_; }
  size_t step() const { return step_; }
  int b_offset() const { return b_; }
  const ColorTable& table() const { return *table_; }
  const Kernels& kernels() const { return *kernels_; }

  // Coarse a* (ColorTable::CoarseA): within ColorTable::kCoarseErrorBound of
  // A(x, y), one table read. The scans use it to pass over pixels that are
  // clearly not past a threshold.
  int CoarseA(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->CoarseA(p[r_], p[1], p[b_]);
  }
  // The scans' pass over a red region: the first step k in [first, last]
  // whose pixel (RoundToInt of (x, y) + k (dx, dy)) lies outside the frame
  // or has a coarse a* not above `above`; last + 1 if there is none. The
  // same pixels and comparisons as a loop over CoarseA; after the first
  // kScalarSteps, eight steps at a time by the vector kernel where there is
  // one (Kernels::first_not_clearly_above).
  static constexpr int kScalarSteps = 8;
  int FirstNotClearlyAbove(float x, float y, float dx, float dy, int first, int last,
                           float above) const {
    int k = first;
    auto stops = [&](int step) {
      const int px = RoundToInt(x + static_cast<float>(step) * dx);
      const int py = RoundToInt(y + static_cast<float>(step) * dy);
      return !Contains(px, py) || !(static_cast<float>(CoarseA(px, py)) > above);
    };
    // Most scans stop within a few steps: those are not worth the vectors.
    for (const int scalar_end = std::min(last, first + kScalarSteps - 1); k <= scalar_end; ++k) {
      if (stops(k)) return k;
    }
    if (last - k >= 7 && kernels_->first_not_clearly_above && OffsetsFit32()) {
      k = kernels_->first_not_clearly_above(data_, step_, width_, height_, r_,
                                            table_->coarse_a_table(), x, y, dx, dy, k, last, above);
    }
    for (; k <= last; ++k) {
      if (stops(k)) return k;
    }
    return k;
  }
  float A(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->A(p[r_], p[1], p[b_]);
  }
  float L(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->L(p[r_], p[1], p[b_]);
  }
  // ColorTable::Y: compared with ColorTable::YForL(level), the same answer
  // as L(x, y) < level, cheaper.
  int32_t Y(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->Y(p[r_], p[1], p[b_]);
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

  // Whether Sample can read (x, y): its four pixels lie inside the frame
  // (false for NaN).
  bool CanSample(float x, float y) const {
    // The same as (int)x + 1 < width for x >= 0, without a cast of a huge x.
    return x >= 0.f && y >= 0.f && x < static_cast<float>(width_ - 1) &&
           y < static_cast<float>(height_ - 1);
  }
  // Whether Sample can read every point of the segment from (x, y) to
  // (last_x, last_y): both ends strictly inside [0, width - 1) x
  // [0, height - 1), hence every point between them (false for NaN).
  bool SegmentInside(float x, float y, float last_x, float last_y) const {
    const float w1 = static_cast<float>(width_ - 1), h1 = static_cast<float>(height_ - 1);
    return x >= 0.f && y >= 0.f && last_x >= 0.f && last_y >= 0.f && x < w1 && y < h1 &&
           last_x < w1 && last_y < h1;
  }
  // For a readable segment (or point, last = first): whether the AVX2
  // bilinear reads along it (BilinearEdgeChannel8, two bytes past each
  // sample's lower right pixel) stay inside the frame: clear of the last two
  // columns, or of the last two rows.
  bool VectorReadsInside(float x, float y, float last_x, float last_y) const {
    return std::max(x, last_x) < static_cast<float>(width_ - 2) ||
           std::max(y, last_y) < static_cast<float>(height_ - 2);
  }
  // Whether every byte offset into the frame fits the AVX2 paths' 32 bits.
  bool OffsetsFit32() const { return step_ * static_cast<size_t>(height_) < (size_t{1} << 31); }

  // Bilinear sample of a channel at sub-pixel (x, y) (pixel centres at
  // integers). False outside the frame. Single precision: exact to a
  // thousandth of a pixel on frames up to 8k wide.
  bool Sample(float x, float y, const ChannelWeights& w, float* value) const {
    if (!CanSample(x, y)) return false;
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const float tx = x - static_cast<float>(x0), ty = y - static_cast<float>(y0);
    const uint8_t* p = Pixel(x0, y0);
    const uint8_t* q = p + step_;
    // The channel in integers at the four pixels, then one bilinear blend.
    auto channel = [&](const uint8_t* px) { return w.r * px[r_] + w.g * px[1] + w.b * px[b_]; };
    const int c00 = channel(p), c01 = channel(p + 3), c10 = channel(q), c11 = channel(q + 3);
    const float top = static_cast<float>(c00) + static_cast<float>(c01 - c00) * tx;
    const float bottom = static_cast<float>(c10) + static_cast<float>(c11 - c10) * tx;
    *value = top + (bottom - top) * ty;
    return true;
  }

  // Sample() at the n points (x + i dx, y + i dy), i = 0 .. n - 1, into
  // out[0 .. n - 1]. False (out undefined) if any point lies outside. The
  // frame test is made once for the segment's two ends, and the two
  // channels the detector uses have their own loops: the sub-pixel side
  // searches spend most of their time here.
  bool SampleLine(float x, float y, float dx, float dy, int n, const ChannelWeights& w,
                  float* out) const {
    const float last_x = x + static_cast<float>(n - 1) * dx;
    const float last_y = y + static_cast<float>(n - 1) * dy;
    if (!SegmentInside(x, y, last_x, last_y)) return false;
    const bool gray = w.r == 1 && w.g == 1 && w.b == 1;
    const bool red_minus_green = w.r == 1 && w.g == -1 && w.b == 0;
    int done = 0;
    // Eight samples at a time by the vector kernel where there is one, its
    // reads stay inside the frame and its byte offsets fit in 32 bits.
    if ((gray || red_minus_green) && kernels_->sample_line && OffsetsFit32() &&
        VectorReadsInside(x, y, last_x, last_y)) {
      done = kernels_->sample_line(data_, step_, r_, gray, x, y, dx, dy, n, out);
    }
    if (gray) {
      SampleLineWith(x, y, dx, dy, done, n, out, [](const uint8_t* px, int, int) {
        return static_cast<int>(px[0]) + px[1] + px[2];
      });
    } else if (red_minus_green) {
      SampleLineWith(x, y, dx, dy, done, n, out,
                     [](const uint8_t* px, int r, int) { return static_cast<int>(px[r]) - px[1]; });
    } else {
      SampleLineWith(x, y, dx, dy, done, n, out, [&w](const uint8_t* px, int r, int b) {
        return w.r * px[r] + w.g * px[1] + w.b * px[b];
      });
    }
    return true;
  }

 private:
  template <typename Channel>
  void SampleLineWith(float x, float y, float dx, float dy, int first, int n, float* out,
                      Channel&& channel) const {
    for (int i = first; i < n; ++i) {
      const float px = x + static_cast<float>(i) * dx, py = y + static_cast<float>(i) * dy;
      const int x0 = static_cast<int>(px), y0 = static_cast<int>(py);
      const float tx = px - static_cast<float>(x0), ty = py - static_cast<float>(y0);
      const uint8_t* p = Pixel(x0, y0);
      const uint8_t* q = p + step_;
      const int c00 = channel(p, r_, b_), c01 = channel(p + 3, r_, b_);
      const int c10 = channel(q, r_, b_), c11 = channel(q + 3, r_, b_);
      const float top = static_cast<float>(c00) + static_cast<float>(c01 - c00) * tx;
      const float bottom = static_cast<float>(c10) + static_cast<float>(c11 - c10) * tx;
      out[i] = top + (bottom - top) * ty;
    }
  }

  const uint8_t* data_;
  size_t step_;
  int width_;
  int height_;
  int r_;
  int b_;
  const ColorTable* table_;
  const Kernels* kernels_;
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_
