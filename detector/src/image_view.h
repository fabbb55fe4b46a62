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
#include "kernels/scalar.h"  // RoundToInt

namespace chromatag::internal {

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
      : frame_{image.data,
               image.step[0],
               image.cols,
               image.rows,
               order == PixelOrder::kRgb ? 0 : 2,
               order == PixelOrder::kRgb ? 2 : 0},
        table_(&table),
        kernels_(&kernels) {}

  int width() const { return frame_.width; }
  int height() const { return frame_.height; }
  bool Contains(int x, int y) const { return frame_.Contains(x, y); }
  const uint8_t* Pixel(int x, int y) const { return frame_.Pixel(x, y); }
  uint8_t R(const uint8_t* p) const { return p[frame_.r_offset]; }
  uint8_t G(const uint8_t* p) const { return p[1]; }
  uint8_t B(const uint8_t* p) const { return p[frame_.b_offset]; }
  int r_offset() const { return frame_.r_offset; }
  int b_offset() const { return frame_.b_offset; }
  // The frame as the vector kernels read it.
  const PixelFrame& frame() const { return frame_; }
  const ColorTable& table() const { return *table_; }
  const Kernels& kernels() const { return *kernels_; }

  // Coarse a* (ColorTable::CoarseA): within ColorTable::kCoarseErrorBound of
  // A(x, y), one table read. The scans use it to pass over pixels that are
  // clearly not past a threshold.
  int CoarseA(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->CoarseA(p[frame_.r_offset], p[1], p[frame_.b_offset]);
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
      k = kernels_->first_not_clearly_above(frame_, table_->coarse_a_table(), x, y, dx, dy, k, last,
                                            above);
    }
    for (; k <= last; ++k) {
      if (stops(k)) return k;
    }
    return k;
  }
  float A(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->A(p[frame_.r_offset], p[1], p[frame_.b_offset]);
  }
  float L(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->L(p[frame_.r_offset], p[1], p[frame_.b_offset]);
  }
  // ColorTable::Y: compared with ColorTable::YForL(level), the same answer
  // as L(x, y) < level, cheaper.
  int32_t Y(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->Y(p[frame_.r_offset], p[1], p[frame_.b_offset]);
  }
  LabF Lab(int x, int y) const {
    const uint8_t* p = Pixel(x, y);
    return table_->Lab(p[frame_.r_offset], p[1], p[frame_.b_offset]);
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

  // Whether Sample can read (x, y), and every point of a segment, and
  // whether the AVX2 reads stay inside the frame (PixelFrame).
  bool CanSample(float x, float y) const { return frame_.CanSample(x, y); }
  bool SegmentInside(float x, float y, float last_x, float last_y) const {
    return frame_.SegmentInside(x, y, last_x, last_y);
  }
  bool VectorReadsInside(float x, float y, float last_x, float last_y) const {
    return frame_.VectorReadsInside(x, y, last_x, last_y);
  }
  bool OffsetsFit32() const { return frame_.OffsetsFit32(); }

  // Bilinear sample of a channel at sub-pixel (x, y) (pixel centres at
  // integers). False outside the frame. Single precision: exact to a
  // thousandth of a pixel on frames up to 8k wide.
  bool Sample(float x, float y, const ChannelWeights& w, float* value) const {
    if (!CanSample(x, y)) return false;
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const float tx = x - static_cast<float>(x0), ty = y - static_cast<float>(y0);
    const uint8_t* p = Pixel(x0, y0);
    const uint8_t* q = p + frame_.step;
    // The channel in integers at the four pixels, then one bilinear blend.
    auto channel = [&](const uint8_t* px) {
      return w.r * px[frame_.r_offset] + w.g * px[1] + w.b * px[frame_.b_offset];
    };
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
      done = kernels_->sample_line(frame_, gray, x, y, dx, dy, n, out);
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
      const uint8_t* q = p + frame_.step;
      const int r = frame_.r_offset, b = frame_.b_offset;
      const int c00 = channel(p, r, b), c01 = channel(p + 3, r, b);
      const int c10 = channel(q, r, b), c11 = channel(q + 3, r, b);
      const float top = static_cast<float>(c00) + static_cast<float>(c01 - c00) * tx;
      const float bottom = static_cast<float>(c10) + static_cast<float>(c11 - c10) * tx;
      out[i] = top + (bottom - top) * ty;
    }
  }

  PixelFrame frame_;
  const ColorTable* table_;
  const Kernels* kernels_;
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_IMAGE_VIEW_H_
