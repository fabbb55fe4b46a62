// The vector paths of ImageView (image_view.h): SampleLine (the sub-pixel
// side searches spend most of their time sampling profiles across edges)
// and FirstNotClearlyAbove (the scans' pass over a red region).
#include "image_view.h"

#include "avx2_kernels.h"

namespace chromatag::internal {

#ifdef CHROMATAG_HAVE_AVX2_PATHS
namespace {

// Same arithmetic as ImageView::SampleLineWith, in the same order and
// without fused multiply-adds, so that both paths give the same floats.
__attribute__((target("avx2"))) int SampleLineAvx2Impl(const uint8_t* data, size_t step,
                                                       int r_offset, bool gray, float x, float y,
                                                       float dx, float dy, int n, float* out) {
  const __m128i red_shift = _mm_cvtsi32_si128(8 * r_offset);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 vx = _mm256_set1_ps(x), vy = _mm256_set1_ps(y);
  const __m256 vdx = _mm256_set1_ps(dx), vdy = _mm256_set1_ps(dy);
  const __m256i vstep = _mm256_set1_epi32(static_cast<int>(step));
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 fi = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(i), lane));
    const __m256 px = _mm256_add_ps(vx, _mm256_mul_ps(fi, vdx));
    const __m256 py = _mm256_add_ps(vy, _mm256_mul_ps(fi, vdy));
    _mm256_storeu_ps(out + i, BilinearEdgeChannel8(data, vstep, px, py, gray, red_shift));
  }
  return i;
}

// Same arithmetic as ImageView::FirstNotClearlyAbove's loop (RoundToInt of
// x + k dx without fused multiply-adds), eight steps at a time.
__attribute__((target("avx2"))) int FirstNotClearlyAboveAvx2Impl(
    const uint8_t* data, size_t step, int width, int height, int r_offset, const int8_t* table,
    float x, float y, float dx, float dy, int first, int last, float above) {
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 vx = _mm256_set1_ps(x), vy = _mm256_set1_ps(y);
  const __m256 vdx = _mm256_set1_ps(dx), vdy = _mm256_set1_ps(dy);
  const __m256 vabove = _mm256_set1_ps(above);
  const __m256i vstep = _mm256_set1_epi32(static_cast<int>(step));
  const __m256i three = _mm256_set1_epi32(3);
  const __m256i zero = _mm256_setzero_si256();
  const __m256i vwidth = _mm256_set1_epi32(width), vheight = _mm256_set1_epi32(height);
  // A 32-bit read at a pixel reaches one byte past it: the frame's last
  // pixel is left to the scalar loop.
  const __m256i last_pixel =
      _mm256_set1_epi32(static_cast<int>(step) * (height - 1) + 3 * (width - 1));
  const CoarseALookup lookup = MakeCoarseALookup(r_offset, table);
  const int* base = reinterpret_cast<const int*>(data);
  int k = first;
  for (; k + 7 <= last; k += 8) {
    const __m256 fk = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(k), lane));
    const __m256i px = RoundToInt8(_mm256_add_ps(vx, _mm256_mul_ps(fk, vdx)));
    const __m256i py = RoundToInt8(_mm256_add_ps(vy, _mm256_mul_ps(fk, vdy)));
    const __m256i offset =
        _mm256_add_epi32(_mm256_mullo_epi32(py, vstep), _mm256_mullo_epi32(px, three));
    const __m256i outside = _mm256_or_si256(
        _mm256_or_si256(_mm256_cmpgt_epi32(zero, px), _mm256_cmpgt_epi32(zero, py)),
        _mm256_or_si256(
            _mm256_or_si256(
                _mm256_cmpgt_epi32(px, _mm256_sub_epi32(vwidth, _mm256_set1_epi32(1))),
                _mm256_cmpgt_epi32(py, _mm256_sub_epi32(vheight, _mm256_set1_epi32(1)))),
            _mm256_cmpeq_epi32(offset, last_pixel)));
    if (!_mm256_testz_si256(outside, outside)) break;
    const __m256i coarse = CoarseA8(lookup, _mm256_i32gather_epi32(base, offset, 1));
    const unsigned above_mask = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_cmp_ps(_mm256_cvtepi32_ps(coarse), vabove, _CMP_GT_OQ)));
    if (above_mask != 0xFFu) return k + __builtin_ctz(~above_mask);
  }
  return k;
}

}  // namespace
#endif

int FirstNotClearlyAboveAvx2(const uint8_t* data, size_t step, int width, int height, int r_offset,
                             const int8_t* table, float x, float y, float dx, float dy, int first,
                             int last, float above) {
#ifdef CHROMATAG_HAVE_AVX2_PATHS
  if (CpuHasAvx2()) {
    return FirstNotClearlyAboveAvx2Impl(data, step, width, height, r_offset, table, x, y, dx, dy,
                                        first, last, above);
  }
#endif
  (void)data, (void)step, (void)width, (void)height, (void)r_offset, (void)table, (void)x;
  (void)y, (void)dx, (void)dy, (void)last, (void)above;
  return first;
}

int SampleLineAvx2(const uint8_t* data, size_t step, int r_offset, bool gray, float x, float y,
                   float dx, float dy, int n, float* out) {
#ifdef CHROMATAG_HAVE_AVX2_PATHS
  if (CpuHasAvx2() && n >= 8) {
    return SampleLineAvx2Impl(data, step, r_offset, gray, x, y, dx, dy, n, out);
  }
#endif
  (void)data, (void)step, (void)r_offset, (void)gray, (void)x, (void)y, (void)dx, (void)dy;
  (void)n, (void)out;
  return 0;
}

}  // namespace chromatag::internal
