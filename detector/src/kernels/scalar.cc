#include "kernels/scalar.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace chromatag::internal {

void CoarseRowScalar(const RowSampler& s, int first, int32_t* coarse) {
  const uint8_t* p = s.row + static_cast<ptrdiff_t>(first) * s.pixel_step;
  for (int i = first; i < s.count; ++i, p += s.pixel_step)
    coarse[i] = s.table[((p[s.r] >> 3) << 10) | ((p[1] >> 3) << 5) | (p[s.b] >> 3)];
}

int RisesScalar(const RowSampler& s, int first, int end, const int32_t* coarse, int* rises, int n) {
  for (int i = std::max(1, first); i < end; ++i) {
    if (CoarseRiseAt(s, coarse, i)) rises[n++] = i;
  }
  return n;
}

int ScanRowCoarseScalar(const RowSampler& s, int32_t* coarse, int* rises) {
  CoarseRowScalar(s, 0, coarse);
  return RisesScalar(s, 1, s.count, coarse, rises, 0);
}

const float* LinearGrayTable() {
  static const std::array<float, 768> table = [] {
    std::array<float, 768> t{};
    for (int i = 0; i < 768; ++i) {
      const double e = std::min(1.0, i / 765.0);
      t[i] = static_cast<float>(e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table.data();
}

}  // namespace chromatag::internal
