// The vector path of ImageView::SampleLine (image_view.h): the sub-pixel
// side searches spend most of their time sampling profiles across edges.
#include "image_view.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define CHROMATAG_SAMPLE_LINE_AVX2 1
#endif

namespace chromatag::internal {

#ifdef CHROMATAG_SAMPLE_LINE_AVX2
namespace {

// The channel of the pixel whose three bytes start each 32-bit lane.
__attribute__((target("avx2"))) inline __m256i Channel(__m256i words, bool gray,
                                                       __m128i red_shift) {
  const __m256i byte = _mm256_set1_epi32(0xFF);
  const __m256i g = _mm256_and_si256(_mm256_srli_epi32(words, 8), byte);
  if (gray) {
    return _mm256_add_epi32(_mm256_add_epi32(_mm256_and_si256(words, byte), g),
                            _mm256_and_si256(_mm256_srli_epi32(words, 16), byte));
  }
  return _mm256_sub_epi32(_mm256_and_si256(_mm256_srl_epi32(words, red_shift), byte), g);
}

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
  const __m256i three = _mm256_set1_epi32(3);
  const int* base = reinterpret_cast<const int*>(data);
  int i = 0;
  for (; i + 8 <= n; i += 8) {
    const __m256 fi = _mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(i), lane));
    const __m256 px = _mm256_add_ps(vx, _mm256_mul_ps(fi, vdx));
    const __m256 py = _mm256_add_ps(vy, _mm256_mul_ps(fi, vdy));
    const __m256i x0 = _mm256_cvttps_epi32(px), y0 = _mm256_cvttps_epi32(py);
    const __m256 tx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(x0));
    const __m256 ty = _mm256_sub_ps(py, _mm256_cvtepi32_ps(y0));
    const __m256i p =
        _mm256_add_epi32(_mm256_mullo_epi32(y0, vstep), _mm256_mullo_epi32(x0, three));
    const __m256i q = _mm256_add_epi32(p, vstep);
    const __m256i c00 = Channel(_mm256_i32gather_epi32(base, p, 1), gray, red_shift);
    const __m256i c01 =
        Channel(_mm256_i32gather_epi32(base, _mm256_add_epi32(p, three), 1), gray, red_shift);
    const __m256i c10 = Channel(_mm256_i32gather_epi32(base, q, 1), gray, red_shift);
    const __m256i c11 =
        Channel(_mm256_i32gather_epi32(base, _mm256_add_epi32(q, three), 1), gray, red_shift);
    const __m256 top = _mm256_add_ps(
        _mm256_cvtepi32_ps(c00), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c01, c00)), tx));
    const __m256 bottom = _mm256_add_ps(
        _mm256_cvtepi32_ps(c10), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c11, c10)), tx));
    _mm256_storeu_ps(out + i, _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ty)));
  }
  return i;
}

}  // namespace
#endif

int SampleLineAvx2(const uint8_t* data, size_t step, int r_offset, bool gray, float x, float y,
                   float dx, float dy, int n, float* out) {
#ifdef CHROMATAG_SAMPLE_LINE_AVX2
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  if (has_avx2 && n >= 8) {
    return SampleLineAvx2Impl(data, step, r_offset, gray, x, y, dx, dy, n, out);
  }
#endif
  (void)data, (void)step, (void)r_offset, (void)gray, (void)x, (void)y, (void)dx, (void)dy;
  (void)n, (void)out;
  return 0;
}

}  // namespace chromatag::internal
