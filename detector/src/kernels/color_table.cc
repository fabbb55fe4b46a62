#include "kernels/color_table.h"

#include <algorithm>
#include <cmath>

#include "chromatag/families/color.h"

namespace chromatag::internal {
namespace {

// CIE 1976 f(), as in families/color.cc.
double CieF(double t) {
  constexpr double kEpsilon = 216.0 / 24389.0;
  constexpr double kKappa = 24389.0 / 27.0;
  return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0;
}

// _mm512_mulhrs_epi16 of one lane: (a b + 2^14) >> 15, rounded.
int16_t MulHighRound(int16_t a, int16_t b) {
  return static_cast<int16_t>((static_cast<int32_t>(a) * b + 0x4000) >> 15);
}

}  // namespace

const ColorTable& ColorTable::Get() {
  static const ColorTable table;
  return table;
}

ColorTable::ColorTable(const Gains& gains)
    : gains_(gains), coarse_a_(32 * 32 * 32 + kCoarsePadding, 0) {
  // Each channel's contribution to X/Xn, Y, Z/Zn: the matrix columns of
  // LinearRgbToXyz applied to the channel's gain, divided by the white.
  const double white[3] = {kD65White.X, kD65White.Y, kD65White.Z};
  for (int channel = 0; channel < 3; ++channel) {
    Rgb unit;
    (channel == 0 ? unit.r : channel == 1 ? unit.g : unit.b) = gains[channel];
    const Xyz column = LinearRgbToXyz(unit);
    const double per_unit[3] = {column.X / white[0], column.Y / white[1], column.Z / white[2]};
    for (int v = 0; v < 256; ++v) {
      const double linear = SrgbToLinear(v / 255.0);
      for (int k = 0; k < 3; ++k) {
        xyz_[channel][v][k] =
            static_cast<int32_t>(std::lround(linear * per_unit[k] * (1 << kFixedBits)));
      }
    }
  }
  for (int i = 0; i < (1 << kFBits) + 2; ++i) {
    f_[i] = static_cast<float>(CieF(static_cast<double>(i) / (1 << kFBits)));
  }
  // The computed a*'s tables (FastATables).
  for (int i = 0; i < 64; ++i) {
    fast_a_.linear[i] =
        static_cast<int16_t>(std::lround(SrgbToLinear((4 * i + 1.5) / 255.0) * 32767));
  }
  for (int channel = 0; channel < 3; ++channel) {
    Rgb unit;
    (channel == 0 ? unit.r : channel == 1 ? unit.g : unit.b) = gains[channel];
    const Xyz column = LinearRgbToXyz(unit);
    fast_a_.x_weight[channel] = static_cast<int16_t>(std::lround(column.X / white[0] * 32768));
    fast_a_.y_weight[channel] = static_cast<int16_t>(std::lround(column.Y / white[1] * 32768));
  }
  auto fixed_f = [](int t) { return static_cast<int16_t>(std::lround(CieF(t / 32768.0) * 16384)); };
  for (int i = 0; i < 64; ++i) {
    const int t = i < 32 ? 128 * i : 1024 * (i - 32);
    const int next = i < 32 ? t + 128 : t + 1024;
    fast_a_.f[i] = fixed_f(t);
    fast_a_.f_step[i] = static_cast<int16_t>(fixed_f(next) - fast_a_.f[i]);
  }
  // Coarse a*: the exact a* of each 8x8x8 block's centre colour, gained.
  double centre_linear[32];
  for (int i = 0; i < 32; ++i) centre_linear[i] = SrgbToLinear((i * 8 + 3.5) / 255.0);
  for (int r = 0; r < 32; ++r) {
    for (int g = 0; g < 32; ++g) {
      for (int b = 0; b < 32; ++b) {
        const Rgb centre{gains[0] * centre_linear[r], gains[1] * centre_linear[g],
                         gains[2] * centre_linear[b]};
        const double a = std::clamp(XyzToLab(LinearRgbToXyz(centre)).a, -127.0, 127.0);
        coarse_a_[(r << 10) | (g << 5) | b] = static_cast<int8_t>(std::lround(a));
      }
    }
  }
}

namespace {

// X/Xn and Y of an 8-bit colour as FastA and the vector code sum them: 16-bit
// sums, as the vector code's lanes. No overflow: each set of weights adds up
// to 32768 within one unit and linear light stays below 32331, so a sum
// stays below 32400.
void FastSums(const ColorTable::FastATables& t, uint8_t r, uint8_t g, uint8_t b, uint16_t* x,
              uint16_t* y) {
  const int16_t linear[3] = {t.linear[r >> 2], t.linear[g >> 2], t.linear[b >> 2]};
  *x = *y = 0;
  for (int c = 0; c < 3; ++c) {
    *x = static_cast<uint16_t>(*x + MulHighRound(linear[c], t.x_weight[c]));
    *y = static_cast<uint16_t>(*y + MulHighRound(linear[c], t.y_weight[c]));
  }
}

}  // namespace

int ColorTable::FastY(uint8_t r, uint8_t g, uint8_t b) const {
  uint16_t x = 0, y = 0;
  FastSums(fast_a_, r, g, b, &x, &y);
  return y;
}

int ColorTable::FastA(uint8_t r, uint8_t g, uint8_t b) const {
  const FastATables& t = fast_a_;
  // Clamped below 1.0 before f().
  uint16_t x = 0, y = 0;
  FastSums(t, r, g, b, &x, &y);
  auto f = [&t](uint16_t v) -> int16_t {
    v = std::min<uint16_t>(v, 32767);
    const bool low = v < 4096;
    const int i = low ? v >> 7 : 32 + (v >> 10);
    // The remainder at the top of a signed word: (v & 127) << 8 or (v & 1023) << 5.
    const int fraction = low ? (v & 127) << 8 : (v & 1023) << 5;
    return static_cast<int16_t>(t.f[i] + MulHighRound(t.f_step[i], static_cast<int16_t>(fraction)));
  };
  return f(x) - f(y);
}

int32_t ColorTable::YForL(float level) const {
  // Bisection over [0, Y of white + 1]: L* of Y never decreases (f() is
  // interpolated between increasing table entries), so the Y where it first
  // reaches `level` is one number. `!(L < level)` also sends NaN to the end.
  int32_t lo = 0, hi = Y(255, 255, 255) + 1;  // The answer lies in [lo, hi].
  while (lo < hi) {
    const int32_t mid = lo + (hi - lo) / 2;
    if (!(LOfY(mid) < level)) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return lo;
}

void ColorTable::Prefetch(bool coarse) const {
  constexpr size_t kLine = 64;
  // Volatile reads: they are made although their values are not used.
  auto stream = [](const void* data, size_t bytes) {
    const auto* p = static_cast<const volatile uint8_t*>(data);
    for (size_t i = 0; i < bytes; i += kLine) static_cast<void>(p[i]);
  };
  if (coarse) stream(coarse_a_.data(), coarse_a_.size());
  stream(xyz_, sizeof(xyz_));
  stream(f_, sizeof(f_));
  stream(&fast_a_, sizeof(fast_a_));
}

int ColorTable::coarse_lines() const {
  const auto begin = reinterpret_cast<uintptr_t>(coarse_a_.data());
  const uintptr_t end = begin + coarse_a_.size();
  return static_cast<int>((end + 63) / 64 - begin / 64);
}

void ColorTable::PrefetchCoarseLines(int first, int count) const {
  // Lines counted from the one holding the table's first byte (a vector's
  // data need not start on a line).
  const auto* line0 =
      reinterpret_cast<const char*>(reinterpret_cast<uintptr_t>(coarse_a_.data()) & ~uintptr_t{63});
  const int end = std::min(first + count, coarse_lines());
  for (int line = std::max(first, 0); line < end; ++line) __builtin_prefetch(line0 + 64 * line);
}

}  // namespace chromatag::internal
