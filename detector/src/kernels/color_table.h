// Compact 8-bit sRGB -> CIELAB tables for the detector (spec section 5).
// Internal to the detector (kernels.h says what else lives here).
//
// The authors hashed every 8-bit colour (384 MiB, 3 s to build). Here two
// small tables do the work, built from the exact formulas of
// families/color.h in about a millisecond:
//
// - the accurate path: per-channel tables of each channel's linear-light
//   contribution to X/Xn, Y and Z/Zn in fixed point, then the CIELAB f()
//   from a 4097-entry table with linear interpolation. Within 0.01 units of
//   the exact formula in L*, a* and b* (checked over all 16.7 million colours
//   by a test). Used wherever a decision is taken.
// - the coarse a* table: a* of the centre of every 8x8x8 block of 8-bit
//   colours, one signed byte each (32 KiB, fits in L1). FindADiff only uses
//   it as a conservative prefilter: a coarse a* is within kCoarseErrorBound of
//   the exact a*, so a rise that could exceed ADiffThresh is always re-checked
//   with the accurate path and none is missed.
// - the computed a*: FindADiff's AVX-512 path computes a* instead of looking
//   it up, in 16-bit fixed point from 448 bytes of tables (FastATables):
//   each channel's linear light from its top six bits, X/Xn and Y as
//   weighted sums, and f() interpolated on two ranges of one table. Within
//   kFastAErrorBound of the accurate path for every colour (a test checks all
//   16.7 million), twice as tight as the coarse table, so fewer rises need
//   the accurate re-check, and without the coarse table's random reads.
//
// A camera's white balance (DetectorOptions::white_balance: per-channel gains
// on linear light, the largest 1) is folded into all three when a table is
// built for it: into the per-channel linear tables, the coarse table's
// colours and the computed a*'s channel weights, so that a detector with a
// white balance does no more work per pixel than one without. Every bound
// above holds for the gained colour: the table's L*, a*, b* of (r, g, b) are
// those of the linear colour (g_r R, g_g G, g_b B).
//
// A ColorTable is immutable after construction and safe to share between
// threads.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_COLOR_TABLE_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_COLOR_TABLE_H_

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace chromatag::internal {

// L*, a*, b* in single precision (true CIELAB, D65).
struct LabF {
  float L = 0.f;
  float a = 0.f;
  float b = 0.f;
};

class ColorTable {
 public:
  // Largest |coarse a* - exact a*| over all 8-bit colours, in a* units
  // (measured 5.7 and checked by a test; rounded up).
  static constexpr int kCoarseErrorBound = 6;

  // Per-channel gains on linear light, R, G, B.
  using Gains = std::array<double, 3>;
  static constexpr Gains kNoGains = {1.0, 1.0, 1.0};

  // The process-wide table without gains, built on first use (thread-safe).
  static const ColorTable& Get();

  // A table for `gains`: each in (0, 1] (DetectorOptions::IsValid holds
  // them to the range the bounds are tested for), so X/Xn and Y stay in
  // [0, 1] and the fixed-point ranges hold.
  explicit ColorTable(const Gains& gains = kNoGains);

  const Gains& gains() const { return gains_; }

  LabF Lab(uint8_t r, uint8_t g, uint8_t b) const {
    const int x = xyz_[0][r][0] + xyz_[1][g][0] + xyz_[2][b][0];
    const int y = xyz_[0][r][1] + xyz_[1][g][1] + xyz_[2][b][1];
    const int z = xyz_[0][r][2] + xyz_[1][g][2] + xyz_[2][b][2];
    const float fx = F(x), fy = F(y), fz = F(z);
    return {116.f * fy - 16.f, 500.f * (fx - fy), 200.f * (fy - fz)};
  }
  float A(uint8_t r, uint8_t g, uint8_t b) const {
    const int x = xyz_[0][r][0] + xyz_[1][g][0] + xyz_[2][b][0];
    const int y = xyz_[0][r][1] + xyz_[1][g][1] + xyz_[2][b][1];
    return 500.f * (F(x) - F(y));
  }
  float L(uint8_t r, uint8_t g, uint8_t b) const { return LOfY(Y(r, g, b)); }
  // CIELAB of the colour whose linear R, G, B are the 8-bit colour's times
  // `gain` (each channel clipped at full scale): a colour seen under another
  // light. Within the accurate path's bound of the exact formula.
  LabF Lab(uint8_t r, uint8_t g, uint8_t b, const std::array<float, 3>& gain) const {
    auto clipped = [](float v) {
      return static_cast<int>(std::min(v, static_cast<float>(1 << kFixedBits)));
    };
    // Each channel's contribution, scaled and clipped at the channel's full
    // scale (its value at 255): X/Xn, Y and Z/Zn of full scale sum to 1.
    int xyz[3] = {0, 0, 0};
    const uint8_t v[3] = {r, g, b};
    for (int c = 0; c < 3; ++c) {
      const float scale =
          std::min(gain[c], static_cast<float>(xyz_[c][255][1]) / std::max(1, xyz_[c][v[c]][1]));
      for (int k = 0; k < 3; ++k) xyz[k] += static_cast<int>(scale * xyz_[c][v[c]][k]);
    }
    const float fx = F(clipped(static_cast<float>(xyz[0]))),
                fy = F(clipped(static_cast<float>(xyz[1]))),
                fz = F(clipped(static_cast<float>(xyz[2])));
    return {116.f * fy - 16.f, 500.f * (fx - fy), 200.f * (fy - fz)};
  }
  // Relative luminance Y in fixed point (1.0 is 1 << 20): L() is L* of this
  // Y, and never smaller for a larger Y. So a test of many colours against
  // one L* level can compare Y with YForL(level) instead, which needs three
  // table reads and no f(): L(r, g, b) < level exactly when
  // Y(r, g, b) < YForL(level).
  int32_t Y(uint8_t r, uint8_t g, uint8_t b) const {
    return xyz_[0][r][1] + xyz_[1][g][1] + xyz_[2][b][1];
  }
  // The least Y (as Y() returns) whose L* is at least `level`; one more than
  // any Y() when none is (a level above white's, or NaN).
  int32_t YForL(float level) const;
  // Coarse a*, see above.
  int CoarseA(uint8_t r, uint8_t g, uint8_t b) const {
    return coarse_a_[((r >> 3) << 10) | ((g >> 3) << 5) | (b >> 3)];
  }
  // 32 * 32 * 32 entries followed by kCoarsePadding zero bytes, so that a
  // 4-byte load at any entry stays inside (SIMD gathers read 32-bit words).
  const int8_t* coarse_a_table() const { return coarse_a_.data(); }
  static constexpr int kCoarsePadding = 4;

  // The computed a* (see above), in units of 1 / kFastAUnitsPerA. FastA is
  // the scalar reference: the vector code gives the same number for every
  // colour, and |FastA / kFastAUnitsPerA - A| <= kFastAErrorBound (measured
  // 2.646; both checked by tests over all 16.7 million colours).
  static constexpr float kFastAUnitsPerA = 16384.f / 500.f;
  static constexpr float kFastAErrorBound = 2.7f;
  struct FastATables {
    // Linear light (1.0 is 32767, so that it fits a signed word) of each
    // 8-bit value's top six bits, taken at the centre of its four values.
    alignas(64) int16_t linear[64];
    // f() (1.0 is 16384) on t = X/Xn or Y (1.0 is 32768), with the step to
    // the next entry: entry i < 32 at t = 128 i (below 1/8, where f() is
    // steepest), entry i >= 36 at t = 1024 (i - 32); 32-35 are not used.
    alignas(64) int16_t f[64];
    alignas(64) int16_t f_step[64];
    // Each channel's weight (1.0 is 32768) in X/Xn and in Y; each set adds
    // up to 32768 within rounding (X/Xn: 32769).
    int16_t x_weight[3], y_weight[3];
  };
  const FastATables& fast_a_tables() const { return fast_a_; }
  int FastA(uint8_t r, uint8_t g, uint8_t b) const;
  // The luminance Y the computed a* is found from (1.0 is 32768; FastA's
  // y), as the vector code computes it: within a few per cent of the
  // accurate Y, as each channel is read at its top six bits.
  int FastY(uint8_t r, uint8_t g, uint8_t b) const;

  // Reads every cache line of the tables once, in order, so that they are
  // in the caches before a frame's random lookups start. A detector called
  // once per frame, with other work in between (the camera driver, the
  // rest of a robot's pipeline, other detectors), otherwise takes a cache
  // miss on each first lookup of a line, one after another; streamed in
  // order, the 58 KiB arrive with many reads in flight at once. With
  // `coarse` false the coarse a* table (32 KiB) is left out, for a caller
  // that brings it in by PrefetchCoarseLines while it works on other things.
  void Prefetch(bool coarse = true) const;
  // Hints (no waiting) that lines [first, first + count) of the coarse a*
  // table's coarse_lines() cache lines will be read soon; lines past either
  // end are ignored.
  void PrefetchCoarseLines(int first, int count) const;
  int coarse_lines() const;

  size_t memory_bytes() const {
    return sizeof(xyz_) + sizeof(f_) + coarse_a_.size() + sizeof(fast_a_);
  }

 private:
  // Fixed point for X/Xn, Y, Z/Zn: 1.0 is 1 << kFixedBits.
  static constexpr int kFixedBits = 20;
  // f() is tabulated at 1 << kFBits steps over [0, 1].
  static constexpr int kFBits = 12;

  float LOfY(int32_t y) const { return 116.f * F(y) - 16.f; }
  float F(int t) const {
    // t in [0, 1 << kFixedBits]; clamp guards the last entry.
    constexpr int kShift = kFixedBits - kFBits;
    const int i = t >> kShift;
    const float frac = static_cast<float>(t & ((1 << kShift) - 1)) * (1.f / (1 << kShift));
    return f_[i] + (f_[i + 1] - f_[i]) * frac;
  }

  Gains gains_;
  int32_t xyz_[3][256][3];
  float f_[(1 << kFBits) + 2];
  std::vector<int8_t> coarse_a_;
  FastATables fast_a_;
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_COLOR_TABLE_H_
