// What the detector's AVX2 paths share: whether the CPU has AVX2, and the
// coarse a* (ColorTable::CoarseA) of eight pixels at once, used by FindADiff
// and ImageView::FirstNotClearlyAbove. Internal; CoarseA8 and
// MakeCoarseALookup only for functions compiled with
// __attribute__((target("avx2"))).
#ifndef CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_
#define CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define CHROMATAG_HAVE_AVX2_PATHS 1

#include <immintrin.h>

#include <cstdint>

namespace chromatag::internal {

// Whether the running CPU has AVX2 (the paths are chosen at run time, so
// that a portable build runs anywhere).
inline bool CpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// The shifts that bring each channel's top five bits down in a pixel's
// 32-bit word (its three bytes first, in either order), and the table.
struct CoarseALookup {
  __m128i shift_r, shift_g, shift_b;
  const int* table;  // ColorTable::coarse_a_table(), padded for 32-bit reads.
};

__attribute__((target("avx2"))) inline CoarseALookup MakeCoarseALookup(int r_offset,
                                                                       const int8_t* table) {
  return {_mm_cvtsi32_si128(8 * r_offset + 3), _mm_cvtsi32_si128(8 + 3),
          _mm_cvtsi32_si128(8 * (2 - r_offset) + 3), reinterpret_cast<const int*>(table)};
}

// `words`: eight pixels' bytes as 32-bit lanes (the fourth byte ignored).
// Returns their coarse a*, sign-extended to 32 bits.
__attribute__((target("avx2"))) inline __m256i CoarseA8(const CoarseALookup& lookup,
                                                        __m256i words) {
  const __m256i mask5 = _mm256_set1_epi32(0x1F);
  const __m256i r5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_r), mask5);
  const __m256i g5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_g), mask5);
  const __m256i b5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_b), mask5);
  const __m256i index =
      _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32(r5, 10), _mm256_slli_epi32(g5, 5)), b5);
  const __m256i entries = _mm256_i32gather_epi32(lookup.table, index, 1);
  return _mm256_srai_epi32(_mm256_slli_epi32(entries, 24), 24);
}

}  // namespace chromatag::internal

#endif
#endif  // CHROMATAG_DETECTOR_SRC_COARSE_A_AVX2_H_
