// The AVX2 kernels (avx2.h, kernels.h), and the pieces they share: RoundToInt
// of eight floats, the coarse a* (ColorTable::CoarseA) of eight pixels, and
// the bilinear edge channel at eight points. Each function is compiled for
// AVX2 alone (CHROMATAG_AVX2), so that a portable build runs anywhere: a
// lambda or helper without the attribute is built for the baseline and does
// not compile there.
#include "kernels/avx2.h"

#include "kernels/kernels.h"

#ifdef CHROMATAG_HAVE_X86_KERNELS

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/scalar.h"

namespace chromatag::internal {
namespace {

// RoundToInt (image_view.h) of eight floats: nearest, halves up.
CHROMATAG_AVX2 inline __m256i RoundToInt8(__m256 v) {
  const __m256 shifted = _mm256_add_ps(v, _mm256_set1_ps(0.5f));
  const __m256i truncated = _mm256_cvttps_epi32(shifted);
  // Truncation rounds towards zero; one less where that rounded up.
  return _mm256_add_epi32(truncated, _mm256_castps_si256(_mm256_cmp_ps(
                                         shifted, _mm256_cvtepi32_ps(truncated), _CMP_LT_OQ)));
}

// The shifts that bring each channel's top five bits down in a pixel's
// 32-bit word (its three bytes first, in either order), and the table.
struct CoarseALookup {
  __m128i shift_r, shift_g, shift_b;
  const int* table;  // ColorTable::coarse_a_table(), padded for 32-bit reads.
};

CHROMATAG_AVX2 inline CoarseALookup MakeCoarseALookup(int r_offset, const int8_t* table) {
  return {_mm_cvtsi32_si128(8 * r_offset + 3), _mm_cvtsi32_si128(8 + 3),
          _mm_cvtsi32_si128(8 * (2 - r_offset) + 3), reinterpret_cast<const int*>(table)};
}

// `words`: eight pixels' bytes as 32-bit lanes (the fourth byte ignored).
// Returns their coarse a*, sign-extended to 32 bits.
CHROMATAG_AVX2 inline __m256i CoarseA8(const CoarseALookup& lookup, __m256i words) {
  const __m256i mask5 = _mm256_set1_epi32(0x1F);
  const __m256i r5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_r), mask5);
  const __m256i g5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_g), mask5);
  const __m256i b5 = _mm256_and_si256(_mm256_srl_epi32(words, lookup.shift_b), mask5);
  const __m256i index =
      _mm256_or_si256(_mm256_or_si256(_mm256_slli_epi32(r5, 10), _mm256_slli_epi32(g5, 5)), b5);
  const __m256i entries = _mm256_i32gather_epi32(lookup.table, index, 1);
  return _mm256_srai_epi32(_mm256_slli_epi32(entries, 24), 24);
}

// `words`: eight pixels' bytes as 32-bit lanes (the fourth byte ignored).
// Returns R + G + B (`gray`) or R - G of each (ChannelWeights kGray and
// kRedMinusGreen); `red_shift` is 8 times the red byte's offset.
CHROMATAG_AVX2 inline __m256i EdgeChannel8(__m256i words, bool gray, __m128i red_shift) {
  const __m256i byte = _mm256_set1_epi32(0xFF);
  const __m256i g = _mm256_and_si256(_mm256_srli_epi32(words, 8), byte);
  if (gray) {
    return _mm256_add_epi32(_mm256_add_epi32(_mm256_and_si256(words, byte), g),
                            _mm256_and_si256(_mm256_srli_epi32(words, 16), byte));
  }
  return _mm256_sub_epi32(_mm256_and_si256(_mm256_srl_epi32(words, red_shift), byte), g);
}

// The low 32 bits of x's 64-bit words and of y's: x0 x1 y0 y1 | x2 x3 y2 y3.
CHROMATAG_AVX2 inline __m256i LowHalves(__m256i x, __m256i y) {
  return _mm256_castps_si256(
      _mm256_shuffle_ps(_mm256_castsi256_ps(x), _mm256_castsi256_ps(y), 0x88));
}

// The bytes at `offsets` (eight 32-bit lanes) and the three bytes after
// them's, as two sets of 32-bit lanes: each lane's pixel and the next pixel
// in its row. Two 64-bit gathers of four, instead of two 32-bit gathers of
// eight. Each read reaches two bytes past the next pixel.
CHROMATAG_AVX2 inline void GatherPixelPairs8(const uint8_t* data, __m256i offsets, __m256i* left,
                                             __m256i* right) {
  // Lanes 0, 1, 4, 5 and 2, 3, 6, 7: _mm256_shuffle_ps(a, b, 0x88) then
  // puts the low halves of a's and b's 64-bit words back in lane order.
  const __m128i first = _mm256_castsi256_si128(
      _mm256_permutevar8x32_epi32(offsets, _mm256_setr_epi32(0, 1, 4, 5, 0, 0, 0, 0)));
  const __m128i second = _mm256_castsi256_si128(
      _mm256_permutevar8x32_epi32(offsets, _mm256_setr_epi32(2, 3, 6, 7, 0, 0, 0, 0)));
  const auto* base = reinterpret_cast<const long long*>(data);
  const __m256i a = _mm256_i32gather_epi64(base, first, 1);
  const __m256i b = _mm256_i32gather_epi64(base, second, 1);
  *left = LowHalves(a, b);
  *right = LowHalves(_mm256_srli_epi64(a, 24), _mm256_srli_epi64(b, 24));
}

// ImageView::Sample of the edge channel at eight points (pixel centres at
// integers), in the same arithmetic and order, without fused multiply-adds,
// so that the floats are the same. The caller guarantees that each point's
// four pixels lie inside the frame and that a read of two bytes past the
// lower right one does too.
CHROMATAG_AVX2 inline __m256 BilinearEdgeChannel8(const uint8_t* data, __m256i step, __m256 px,
                                                  __m256 py, bool gray, __m128i red_shift) {
  const __m256i three = _mm256_set1_epi32(3);
  const __m256i x0 = _mm256_cvttps_epi32(px), y0 = _mm256_cvttps_epi32(py);
  const __m256 tx = _mm256_sub_ps(px, _mm256_cvtepi32_ps(x0));
  const __m256 ty = _mm256_sub_ps(py, _mm256_cvtepi32_ps(y0));
  const __m256i p = _mm256_add_epi32(_mm256_mullo_epi32(y0, step), _mm256_mullo_epi32(x0, three));
  __m256i w00, w01, w10, w11;
  GatherPixelPairs8(data, p, &w00, &w01);
  GatherPixelPairs8(data, _mm256_add_epi32(p, step), &w10, &w11);
  const __m256i c00 = EdgeChannel8(w00, gray, red_shift);
  const __m256i c01 = EdgeChannel8(w01, gray, red_shift);
  const __m256i c10 = EdgeChannel8(w10, gray, red_shift);
  const __m256i c11 = EdgeChannel8(w11, gray, red_shift);
  const __m256 top = _mm256_add_ps(
      _mm256_cvtepi32_ps(c00), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c01, c00)), tx));
  const __m256 bottom = _mm256_add_ps(
      _mm256_cvtepi32_ps(c10), _mm256_mul_ps(_mm256_cvtepi32_ps(_mm256_sub_epi32(c11, c10)), tx));
  return _mm256_add_ps(top, _mm256_mul_ps(_mm256_sub_ps(bottom, top), ty));
}

// N = 4 (samples 12 bytes apart): the words of the eight samples from
// `bytes` on, two samples in each 16-byte load, picked into 32-bit lanes by
// byte shuffles (cheaper than a gather). Lanes hold samples 0 1 4 5 |
// 2 3 6 7: the caller puts them in order after the table lookup.
CHROMATAG_AVX2 inline __m256i PickSamples12(const uint8_t* bytes) {
  const __m256i pick_low =
      _mm256_setr_epi8(0, 1, 2, -1, 12, 13, 14, -1, -1, -1, -1, -1, -1, -1, -1, -1, 0, 1, 2, -1, 12,
                       13, 14, -1, -1, -1, -1, -1, -1, -1, -1, -1);
  const __m256i pick_high =
      _mm256_setr_epi8(-1, -1, -1, -1, -1, -1, -1, -1, 0, 1, 2, -1, 12, 13, 14, -1, -1, -1, -1, -1,
                       -1, -1, -1, -1, 0, 1, 2, -1, 12, 13, 14, -1);
  const __m256i first =
      _mm256_set_m128i(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 24)),
                       _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes)));
  const __m256i second =
      _mm256_set_m128i(_mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 72)),
                       _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + 48)));
  return _mm256_or_si256(_mm256_shuffle_epi8(first, pick_low),
                         _mm256_shuffle_epi8(second, pick_high));
}

// coarse[0 .. returned): the row's coarse a*, eight samples per step: each
// sample's 3 bytes as a 32-bit word (the fourth byte ignored), the table
// index from shifts and masks, a gather from the coarse table (padded for
// the 32-bit reads). A word read at a sample reaches one byte past its
// pixel: the row's last sample is left to the scalar loop.
CHROMATAG_AVX2 inline int CoarseRowAvx2(const RowSampler& s, int32_t* coarse) {
  const int vector_count = s.count - 1;
  const __m256i offsets = _mm256_mullo_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
                                             _mm256_set1_epi32(s.pixel_step));
  const CoarseALookup lookup = MakeCoarseALookup(s.r, s.table);
  const __m256i in_order = _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7);
  int i = 0;
  for (; i + 8 <= vector_count; i += 8) {
    const uint8_t* bytes = s.row + static_cast<ptrdiff_t>(i) * s.pixel_step;
    const __m256i words = s.pixel_step == 12 ? PickSamples12(bytes)
                                             : _mm256_i32gather_epi32(
                                                   reinterpret_cast<const int*>(bytes), offsets, 1);
    __m256i a = CoarseA8(lookup, words);
    if (s.pixel_step == 12) a = _mm256_permutevar8x32_epi32(a, in_order);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(coarse + i), a);
  }
  return i;
}

// CoarseRiseAt for the samples from *first on, eight at a time: appends
// those that may seed to rises[n ..] and returns the new count; *first
// ends on the first sample not tested. Each sample needs the two before it.
CHROMATAG_AVX2 inline int RisesAvx2(const RowSampler& s, const int32_t* coarse, int* first,
                                    int* rises, int n) {
  const __m256i threshold = _mm256_set1_epi32(s.threshold);
  // No luminance here: every rise over the dim light's lower bar is listed.
  const __m256i two_step_thresh = _mm256_set1_epi32(s.dim_two_step_thresh);
  const __m256i step_thresh = _mm256_set1_epi32(s.step_thresh);
  const __m256i green_limit = _mm256_set1_epi32(s.green_limit);
  const __m256i red_floor = _mm256_set1_epi32(s.red_floor);
  int j = *first;
  for (; j + 8 <= s.count; j += 8) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j));
    const __m256i before = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j - 1));
    const __m256i two_before = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(coarse + j - 2));
    const __m256i rise = _mm256_sub_epi32(a, before);
    const __m256i two_step = _mm256_and_si256(
        _mm256_and_si256(_mm256_and_si256(_mm256_cmpgt_epi32(green_limit, two_before),
                                          _mm256_cmpgt_epi32(a, red_floor)),
                         _mm256_cmpgt_epi32(_mm256_sub_epi32(a, two_before), two_step_thresh)),
        _mm256_and_si256(_mm256_cmpgt_epi32(rise, step_thresh),
                         _mm256_cmpgt_epi32(_mm256_sub_epi32(before, two_before), step_thresh)));
    const __m256i seeds = _mm256_or_si256(_mm256_cmpgt_epi32(rise, threshold), two_step);
    unsigned mask = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(seeds)));
    while (mask) {
      rises[n++] = j + __builtin_ctz(mask);
      mask &= mask - 1;
    }
  }
  *first = j;
  return n;
}

}  // namespace

// The coarse a* eight samples at a time (CoarseRowAvx2), then eight
// differences per compare (RisesAvx2). Compiled for AVX2 alone and called
// only when the CPU has it.
CHROMATAG_AVX2 int ScanRowCoarseAvx2(const RowSampler& s, int32_t* coarse, int* rises) {
  CoarseRowScalar(s, CoarseRowAvx2(s, coarse), coarse);
  // Sample 1 has no sample two before it: the scalar test.
  int n = RisesScalar(s, 1, std::min(2, s.count), coarse, rises, 0);
  int j = 2;
  n = RisesAvx2(s, coarse, &j, rises, n);
  return RisesScalar(s, j, s.count, coarse, rises, n);
}

// Same arithmetic as ImageView::SampleLineWith, in the same order and
// without fused multiply-adds, so that both paths give the same floats.
CHROMATAG_AVX2 int SampleLineAvx2(const PixelFrame& frame, bool gray, float x, float y, float dx,
                                  float dy, int n, float* out) {
  if (n < 8) return 0;
  const uint8_t* data = frame.data;
  const __m128i red_shift = _mm_cvtsi32_si128(8 * frame.r_offset);
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 vx = _mm256_set1_ps(x), vy = _mm256_set1_ps(y);
  const __m256 vdx = _mm256_set1_ps(dx), vdy = _mm256_set1_ps(dy);
  const __m256i vstep = _mm256_set1_epi32(static_cast<int>(frame.step));
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
CHROMATAG_AVX2 int FirstNotClearlyAboveAvx2(const PixelFrame& frame, const int8_t* table, float x,
                                            float y, float dx, float dy, int first, int last,
                                            float above) {
  const uint8_t* data = frame.data;
  const size_t step = frame.step;
  const int width = frame.width, height = frame.height, r_offset = frame.r_offset;
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

namespace {

// The lanes whose profile has a sample i (`length` samples each).
CHROMATAG_AVX2 inline __m256 BelowLength(__m256i length, int i) {
  return _mm256_castsi256_ps(_mm256_cmpgt_epi32(length, _mm256_set1_epi32(i)));
}

// LinearGray on eight values.
CHROMATAG_AVX2 inline __m256 LinearGray8(__m256 gray, const float* table) {
  const __m256 x = _mm256_min_ps(_mm256_max_ps(gray, _mm256_setzero_ps()), _mm256_set1_ps(765.f));
  const __m256i i = _mm256_cvttps_epi32(x);
  const __m256 low = _mm256_i32gather_ps(table, i, 4);
  const __m256 high = _mm256_i32gather_ps(table, _mm256_add_epi32(i, _mm256_set1_epi32(1)), 4);
  const __m256 t = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
  return _mm256_add_ps(low, _mm256_mul_ps(t, _mm256_sub_ps(high, low)));
}

// For NearestCrossings8: where a lane crosses (`crosses`) at `at` nearer
// its centre than its best so far, in double, that crossing becomes its
// best. Lanes 0-3 are in best[0], 4-7 in best[1].
CHROMATAG_AVX2 inline void KeepNearerCrossings(__m256 at, __m256 crosses,
                                               const __m256d* centre_half, __m256d abs_mask,
                                               __m256d* best, __m256d* best_distance) {
  const __m128 at_half[2] = {_mm256_castps256_ps128(at), _mm256_extractf128_ps(at, 1)};
  const __m128i crosses_half[2] = {_mm256_castsi256_si128(_mm256_castps_si256(crosses)),
                                   _mm256_extracti128_si256(_mm256_castps_si256(crosses), 1)};
  for (int h = 0; h < 2; ++h) {
    const __m256d at_d = _mm256_cvtps_pd(at_half[h]);
    const __m256d distance = _mm256_and_pd(_mm256_sub_pd(at_d, centre_half[h]), abs_mask);
    const __m256d nearer =
        _mm256_and_pd(_mm256_castsi256_pd(_mm256_cvtepi32_epi64(crosses_half[h])),
                      _mm256_cmp_pd(distance, best_distance[h], _CMP_LT_OQ));
    best[h] = _mm256_blendv_pd(best[h], at_d, nearer);
    best_distance[h] = _mm256_blendv_pd(best_distance[h], distance, nearer);
  }
}

// EdgePoints8Avx2's profiles, one per lane: the first sample, the step
// between samples, the number of samples and of steps either side of the
// middle. Lanes not in the vector path read a safe pixel and are ignored.
struct ProfileLanes {
  alignas(32) float start_x[8], start_y[8], step_x[8], step_y[8];
  alignas(32) int length[8], steps[8];
  bool in_vector[8];
  int longest = 0;  // The most samples of any lane.
};

// The lanes of spec[0 .. count), as EdgePoint lays out each profile; out[]
// not found. Returns the profiles left to the caller's EdgePoint: those
// whose vector reads would pass the frame's last byte.
CHROMATAG_AVX2 inline unsigned SetUpProfileLanes(const PixelFrame& frame, const ProfileSpec* spec,
                                                 int count, ProfileEdge* out, ProfileLanes* lanes) {
  unsigned left_over = 0;
  for (int l = 0; l < 8; ++l) {
    lanes->in_vector[l] = false;
    lanes->start_x[l] = lanes->start_y[l] = 1.f;
    lanes->step_x[l] = lanes->step_y[l] = 0.f;
    lanes->length[l] = lanes->steps[l] = 0;
    if (l >= count) continue;
    out[l].found = false;
    const float ox = static_cast<float>(spec[l].outward.x) * kProfileStep,
                oy = static_cast<float>(spec[l].outward.y) * kProfileStep;
    const int s = static_cast<int>(
        std::min<double>(kMaxProfileSteps, std::ceil(spec[l].half / kProfileStep)));
    const int n = 2 * s + 1;
    const float first = static_cast<float>(-s);
    const float x = static_cast<float>(spec[l].middle.x) + first * ox;
    const float y = static_cast<float>(spec[l].middle.y) + first * oy;
    const float last_x = x + static_cast<float>(n - 1) * ox;
    const float last_y = y + static_cast<float>(n - 1) * oy;
    // Where ImageView::SampleLine fails, so does EdgePoint.
    if (!frame.SegmentInside(x, y, last_x, last_y)) continue;
    if (!frame.VectorReadsInside(x, y, last_x, last_y)) {
      left_over |= 1u << l;
      continue;
    }
    lanes->in_vector[l] = true;
    lanes->start_x[l] = x;
    lanes->start_y[l] = y;
    lanes->step_x[l] = ox;
    lanes->step_y[l] = oy;
    lanes->length[l] = n;
    lanes->steps[l] = s;
    lanes->longest = std::max(lanes->longest, n);
  }
  return left_over;
}

// profile[k], k < lanes.longest: each lane's sample k of the edge channel
// (in linear light if `linear`). Past a lane's own end, its first sample is
// read again (and ignored).
CHROMATAG_AVX2 inline void SampleProfiles8(const PixelFrame& frame, bool gray, bool linear,
                                           const ProfileLanes& lanes, __m256i vlength,
                                           __m256* profile) {
  const __m256i step = _mm256_set1_epi32(static_cast<int>(frame.step));
  const __m128i red_shift = _mm_cvtsi32_si128(8 * frame.r_offset);
  const __m256 vx = _mm256_load_ps(lanes.start_x), vy = _mm256_load_ps(lanes.start_y);
  const __m256 vox = _mm256_load_ps(lanes.step_x), voy = _mm256_load_ps(lanes.step_y);
  for (int k = 0; k < lanes.longest; ++k) {
    const __m256 fk = _mm256_set1_ps(static_cast<float>(k));
    const __m256 inside = BelowLength(vlength, k);
    const __m256 px = _mm256_blendv_ps(vx, _mm256_add_ps(vx, _mm256_mul_ps(fk, vox)), inside);
    const __m256 py = _mm256_blendv_ps(vy, _mm256_add_ps(vy, _mm256_mul_ps(fk, voy)), inside);
    profile[k] = BilinearEdgeChannel8(frame.data, step, px, py, gray, red_shift);
    if (linear) profile[k] = LinearGray8(profile[k], LinearGrayTable());
  }
}

// Each lane's steepest change the `polarity` way round (the first of
// equals) into change_lane[], and the sample it is centred on into
// steepest_lane[].
CHROMATAG_AVX2 inline void SteepestChanges8(const __m256* profile, int longest, __m256i vlength,
                                            int polarity, float* change_lane, int* steepest_lane) {
  const __m256 vpolarity = _mm256_set1_ps(static_cast<float>(polarity));
  __m256 steepest_change = _mm256_set1_ps(-1.f);
  __m256 steepest = _mm256_castsi256_ps(_mm256_set1_epi32(1));
  for (int i = 1; i + 1 < longest; ++i) {
    const __m256 change = _mm256_mul_ps(vpolarity, _mm256_sub_ps(profile[i + 1], profile[i - 1]));
    const __m256 steeper = _mm256_and_ps(BelowLength(vlength, i + 1),
                                         _mm256_cmp_ps(change, steepest_change, _CMP_GT_OQ));
    steepest_change = _mm256_blendv_ps(steepest_change, change, steeper);
    steepest = _mm256_blendv_ps(steepest, _mm256_castsi256_ps(_mm256_set1_epi32(i)), steeper);
  }
  _mm256_store_ps(change_lane, steepest_change);
  _mm256_store_si256(reinterpret_cast<__m256i*>(steepest_lane), _mm256_castps_si256(steepest));
}

// Each lane's halfway level between the two levels read half a cell either
// side of its steepest change, and that change's place on the profile (in
// pixels from the middle): where has_mid[l], the lane's levels were read and
// differ by at least the contrast asked for.
struct LevelLanes {
  alignas(32) float mid[8];
  alignas(32) double centre[8];
  bool has_mid[8];
};

// The halfway level of two levels read (encoded), in linear light if asked.
inline float HalfwayLevel(float inside, float outside, bool linear) {
  return linear ? 0.5f * (LinearGray(inside) + LinearGray(outside)) : 0.5f * (inside + outside);
}

// Where each lane reads its two levels (in_x[l] ...), for the lanes whose
// steepest change rose the right way; *read gets the lanes that are read
// eight at a time. A level whose vector read would pass the frame's end
// (its lower right pixel is the frame's last) is read here, one by one.
struct LevelPoints {
  alignas(32) float in_x[8], in_y[8], out_x[8], out_y[8];
  bool read[8];
};
CHROMATAG_AVX2 inline void PlaceLevels8(const PixelFrame& frame, bool gray, bool linear,
                                        const ProfileSpec* spec, const ProfileLanes& lanes,
                                        const float* change_lane, const int* steepest_lane,
                                        float min_contrast, LevelPoints* points,
                                        LevelLanes* levels) {
  for (int l = 0; l < 8; ++l) {
    levels->has_mid[l] = points->read[l] = false;
    points->in_x[l] = points->in_y[l] = points->out_x[l] = points->out_y[l] = 1.f;
    levels->mid[l] = 0.f;
    levels->centre[l] = 0.0;
    if (!lanes.in_vector[l] || !(change_lane[l] > 0.f)) continue;
    const double centre = (steepest_lane[l] - lanes.steps[l]) * kProfileStep;
    levels->centre[l] = centre;
    const cv::Point2d in = spec[l].middle + (centre - spec[l].level_offset) * spec[l].outward;
    const cv::Point2d out = spec[l].middle + (centre + spec[l].level_offset) * spec[l].outward;
    const float ix = static_cast<float>(in.x), iy = static_cast<float>(in.y);
    const float ux = static_cast<float>(out.x), uy = static_cast<float>(out.y);
    // Where ImageView::Sample fails, so does EdgePoint.
    if (!frame.CanSample(ix, iy) || !frame.CanSample(ux, uy)) continue;
    if (!frame.VectorReadsInside(ix, iy, ix, iy) || !frame.VectorReadsInside(ux, uy, ux, uy)) {
      const float inside = SampleEdgeChannel(frame, gray, ix, iy);
      const float outside = SampleEdgeChannel(frame, gray, ux, uy);
      if (std::abs(outside - inside) < min_contrast) continue;
      levels->mid[l] = HalfwayLevel(inside, outside, linear);
      levels->has_mid[l] = true;
      continue;
    }
    points->in_x[l] = ix, points->in_y[l] = iy, points->out_x[l] = ux, points->out_y[l] = uy;
    points->read[l] = true;
  }
}

// The two levels of every lane, the halfway level between them
// (LevelLanes).
CHROMATAG_AVX2 inline void HalfwayLevels8(const PixelFrame& frame, bool gray, bool linear,
                                          const ProfileSpec* spec, const ProfileLanes& lanes,
                                          const float* change_lane, const int* steepest_lane,
                                          float min_contrast, LevelLanes* levels) {
  LevelPoints points;
  PlaceLevels8(frame, gray, linear, spec, lanes, change_lane, steepest_lane, min_contrast, &points,
               levels);
  const __m256i step = _mm256_set1_epi32(static_cast<int>(frame.step));
  const __m128i red_shift = _mm_cvtsi32_si128(8 * frame.r_offset);
  alignas(32) float inside[8], outside[8];
  _mm256_store_ps(inside, BilinearEdgeChannel8(frame.data, step, _mm256_load_ps(points.in_x),
                                               _mm256_load_ps(points.in_y), gray, red_shift));
  _mm256_store_ps(outside, BilinearEdgeChannel8(frame.data, step, _mm256_load_ps(points.out_x),
                                                _mm256_load_ps(points.out_y), gray, red_shift));
  for (int l = 0; l < 8; ++l) {
    if (!points.read[l] || std::abs(outside[l] - inside[l]) < min_contrast) continue;
    levels->mid[l] = HalfwayLevel(inside[l], outside[l], linear);
    levels->has_mid[l] = true;
  }
}

// Each lane's crossing of its halfway level nearest its steepest change,
// in pixels from the middle, compared in double as EdgePoint does, into
// best_lane[]; above 1e299 where it has none (lanes without a level pair
// never cross).
CHROMATAG_AVX2 inline void NearestCrossings8(const __m256* profile, const ProfileLanes& lanes,
                                             __m256i vlength, const LevelLanes& levels,
                                             double* best_lane) {
  const __m256 vmid = _mm256_load_ps(levels.mid);
  const __m256 vsteps =
      _mm256_cvtepi32_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(lanes.steps)));
  const __m256 vprofile_step = _mm256_set1_ps(kProfileStep);
  alignas(32) int may_cross[8];
  for (int l = 0; l < 8; ++l) may_cross[l] = levels.has_mid[l] ? -1 : 0;
  const __m256 vmay_cross =
      _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(may_cross)));
  const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFFLL));
  const __m256d centre_half[2] = {_mm256_load_pd(levels.centre), _mm256_load_pd(levels.centre + 4)};
  __m256d best[2], best_distance[2];
  for (int h = 0; h < 2; ++h) {
    best[h] = _mm256_set1_pd(1e300);
    best_distance[h] = _mm256_and_pd(_mm256_sub_pd(best[h], centre_half[h]), abs_mask);
  }
  for (int i = 1; i < lanes.longest; ++i) {
    const __m256 previous = profile[i - 1], v = profile[i];
    const __m256 straddles =
        _mm256_cmp_ps(_mm256_mul_ps(_mm256_sub_ps(previous, vmid), _mm256_sub_ps(v, vmid)),
                      _mm256_setzero_ps(), _CMP_LE_OQ);
    const __m256 crosses =
        _mm256_and_ps(_mm256_and_ps(vmay_cross, BelowLength(vlength, i)),
                      _mm256_and_ps(straddles, _mm256_cmp_ps(previous, v, _CMP_NEQ_UQ)));
    if (_mm256_testz_ps(crosses, crosses)) continue;
    const __m256 at = _mm256_add_ps(
        _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(static_cast<float>(i - 1)), vsteps),
                      vprofile_step),
        _mm256_div_ps(_mm256_mul_ps(vprofile_step, _mm256_sub_ps(vmid, previous)),
                      _mm256_sub_ps(v, previous)));
    KeepNearerCrossings(at, crosses, centre_half, abs_mask, best, best_distance);
  }
  _mm256_store_pd(best_lane, best[0]);
  _mm256_store_pd(best_lane + 4, best[1]);
}

}  // namespace

// EdgePoint for up to eight profiles at once, one per lane (each with its
// own position, direction and window): the same floats, comparisons and
// choices as EdgePoint for each, so the same edge points. Profiles whose
// reads would pass the frame's last byte are left to the caller's
// EdgePoint. On the camera set, side refinement took about a third less time
// than with EdgePoint profile by profile: the per-profile bookkeeping, the
// sampling and the two level reads are shared across the lanes.
CHROMATAG_AVX2 unsigned EdgePoints8Avx2(const PixelFrame& frame, bool gray, int polarity,
                                        const ProfileSpec* spec, int count, float min_contrast,
                                        ProfileEdge* out, bool linear) {
  ProfileLanes lanes;
  const unsigned left_over = SetUpProfileLanes(frame, spec, count, out, &lanes);
  if (lanes.longest == 0) return left_over;
  const __m256i vlength = _mm256_load_si256(reinterpret_cast<const __m256i*>(lanes.length));
  __m256 profile[2 * kMaxProfileSteps + 1];
  SampleProfiles8(frame, gray, linear, lanes, vlength, profile);
  alignas(32) float change_lane[8];
  alignas(32) int steepest_lane[8];
  SteepestChanges8(profile, lanes.longest, vlength, polarity, change_lane, steepest_lane);
  LevelLanes levels;
  HalfwayLevels8(frame, gray, linear, spec, lanes, change_lane, steepest_lane, min_contrast,
                 &levels);
  alignas(32) double best_lane[8];
  NearestCrossings8(profile, lanes, vlength, levels, best_lane);
  for (int l = 0; l < 8; ++l) {
    if (!levels.has_mid[l] || best_lane[l] > 1e299) continue;
    out[l].found = true;
    out[l].edge = spec[l].middle + best_lane[l] * spec[l].outward;
  }
  return left_over;
}

namespace {

// RoundToInt(static_cast<float>(v)) of eight doubles, `lo` the first four.
CHROMATAG_AVX2 inline __m256i RoundDoublesToInt8(__m256d lo, __m256d hi) {
  return RoundToInt8(_mm256_set_m128(_mm256_cvtpd_ps(hi), _mm256_cvtpd_ps(lo)));
}

// A cell grid's centre and axes in every lane.
struct GridVectors {
  __m256d cx, cy, dux, duy, dvx, dvy;
};
CHROMATAG_AVX2 inline GridVectors MakeGridVectors(const CellGrid& grid) {
  return {_mm256_set1_pd(grid.centre.x), _mm256_set1_pd(grid.centre.y), _mm256_set1_pd(grid.du.x),
          _mm256_set1_pd(grid.du.y),     _mm256_set1_pd(grid.dv.x),     _mm256_set1_pd(grid.dv.y)};
}

// The pixels of the grid's points k .. k + 7: AddGridPoint's coordinates in
// the same double arithmetic, rounded as it rounds.
CHROMATAG_AVX2 inline void GridPixels8(const CellGrid& grid, const GridVectors& v, int k,
                                       __m256i* px, __m256i* py) {
  alignas(32) double s[8], t[8];
  for (int l = 0; l < 8; ++l) {
    s[l] = grid.spread[(k + l) % grid.samples];
    t[l] = grid.spread[(k + l) / grid.samples];
  }
  __m256d x[2], y[2];
  for (int h = 0; h < 2; ++h) {
    const __m256d sv = _mm256_load_pd(s + 4 * h), tv = _mm256_load_pd(t + 4 * h);
    x[h] = _mm256_add_pd(_mm256_add_pd(v.cx, _mm256_mul_pd(sv, v.dux)), _mm256_mul_pd(tv, v.dvx));
    y[h] = _mm256_add_pd(_mm256_add_pd(v.cy, _mm256_mul_pd(sv, v.duy)), _mm256_mul_pd(tv, v.dvy));
  }
  *px = RoundDoublesToInt8(x[0], x[1]);
  *py = RoundDoublesToInt8(y[0], y[1]);
}

// The lanes' sums of R, G and B, added to *sums.
CHROMATAG_AVX2 inline void AddLaneSums(__m256i r, __m256i g, __m256i b, PixelSums* sums) {
  alignas(32) int lanes[3][8];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes[0]), r);
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes[1]), g);
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes[2]), b);
  for (int l = 0; l < 8; ++l) {
    sums->r += lanes[0][l];
    sums->g += lanes[1][l];
    sums->b += lanes[2][l];
  }
}

}  // namespace

// AddGridPoint for the points [0, returned), eight at a time: the same
// coordinates in the same double and float arithmetic, the same rounding and
// frame test, so the same sums. The frame's last pixel (a 32-bit read there
// would pass its end) is left to AddGridPoint. The frame's byte offsets fit
// in 32 bits.
CHROMATAG_AVX2 int AddGridPointsAvx2(const PixelFrame& frame, const CellGrid& grid, int count,
                                     PixelSums* sums) {
  const GridVectors axes = MakeGridVectors(grid);
  const __m256i zero = _mm256_setzero_si256(), byte = _mm256_set1_epi32(0xFF);
  const __m256i last_x = _mm256_set1_epi32(frame.width - 1),
                last_y = _mm256_set1_epi32(frame.height - 1);
  const __m256i step = _mm256_set1_epi32(static_cast<int>(frame.step));
  const __m128i r_shift = _mm_cvtsi32_si128(8 * frame.r_offset),
                b_shift = _mm_cvtsi32_si128(8 * frame.b_offset);
  const int* base = reinterpret_cast<const int*>(frame.data);
  __m256i r = zero, g = zero, b = zero;
  int k = 0;
  for (; k + 8 <= count; k += 8) {
    __m256i px, py;
    GridPixels8(grid, axes, k, &px, &py);
    const __m256i outside = _mm256_or_si256(
        _mm256_or_si256(_mm256_cmpgt_epi32(zero, px), _mm256_cmpgt_epi32(zero, py)),
        _mm256_or_si256(_mm256_cmpgt_epi32(px, last_x), _mm256_cmpgt_epi32(py, last_y)));
    const __m256i at_last =
        _mm256_and_si256(_mm256_cmpeq_epi32(px, last_x), _mm256_cmpeq_epi32(py, last_y));
    if (!_mm256_testz_si256(at_last, at_last)) {
      const unsigned lanes =
          static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(at_last)));
      for (int l = 0; l < 8; ++l) {
        if (lanes >> l & 1u) AddGridPoint(frame, grid, k + l, sums);
      }
    }
    const __m256i read =
        _mm256_andnot_si256(_mm256_or_si256(outside, at_last), _mm256_set1_epi32(-1));
    const __m256i offset = _mm256_add_epi32(_mm256_mullo_epi32(py, step),
                                            _mm256_mullo_epi32(px, _mm256_set1_epi32(3)));
    const __m256i words = _mm256_mask_i32gather_epi32(zero, base, offset, read, 1);
    r = _mm256_add_epi32(r, _mm256_and_si256(_mm256_srl_epi32(words, r_shift), byte));
    g = _mm256_add_epi32(g, _mm256_and_si256(_mm256_srli_epi32(words, 8), byte));
    b = _mm256_add_epi32(b, _mm256_and_si256(_mm256_srl_epi32(words, b_shift), byte));
    sums->n +=
        __builtin_popcount(static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(read))));
  }
  AddLaneSums(r, g, b, sums);
  return k;
}

}  // namespace chromatag::internal

#endif  // CHROMATAG_HAVE_X86_KERNELS
