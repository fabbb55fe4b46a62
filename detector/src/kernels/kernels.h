// The detector's vector kernels and their one dispatch point. Internal.
//
// A kernel is the inner loop of a stage written for one instruction set:
// kernels/avx2.cc and kernels/avx512.cc hold them, kernels/scalar.* the
// scalar loops they must match to the last bit (and fall back to in their
// tails). The stages never test the CPU themselves: a Detector picks one
// Kernels at creation (ForCpu) and every stage reaches it through its
// ImageView. Tests build a view with ForPath to run a given path.
//
// The kernels know no stage: they take plain data (the frame's bytes as a
// PixelFrame, tables, and the small structs below), which the stages fill
// from their own types. No file in kernels/ includes a stage's header
// (detector/CMakeLists.txt checks it).
//
// A null pointer means the path has no vector version of that kernel: the
// caller runs its scalar loop.
//
// The vector kernels are compiled for their instruction set function by
// function (target attributes), so that a portable build (CHROMATAG_NATIVE
// off) runs anywhere and takes them where the CPU has them.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_KERNELS_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_KERNELS_H_

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "kernels/color_table.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define CHROMATAG_HAVE_X86_KERNELS 1
#endif

namespace chromatag::internal {

// The instruction sets, narrowest first. kAvx512 is AVX-512 with byte and
// word lanes and byte permutes (F, BW, VBMI); its kernels that need no
// more than AVX2 are the AVX2 ones.
enum class KernelPath { kScalar, kAvx2, kAvx512 };

// A caller's 8-bit 3-channel frame as the kernels read it: rows `step`
// bytes apart, red and blue at byte offsets `r_offset` and `b_offset` of
// each pixel, green at 1 (ImageView holds one).
struct PixelFrame {
  const uint8_t* data = nullptr;
  size_t step = 0;
  int width = 0;
  int height = 0;
  int r_offset = 2;
  int b_offset = 0;

  bool Contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
  const uint8_t* Pixel(int x, int y) const { return data + y * step + 3 * x; }
  // Whether a bilinear sample at (x, y) can read its four pixels: they lie
  // inside the frame (false for NaN).
  bool CanSample(float x, float y) const {
    // The same as (int)x + 1 < width for x >= 0, without a cast of a huge x.
    return x >= 0.f && y >= 0.f && x < static_cast<float>(width - 1) &&
           y < static_cast<float>(height - 1);
  }
  // Whether bilinear samples can read every point of the segment from
  // (x, y) to (last_x, last_y): both ends strictly inside [0, width - 1) x
  // [0, height - 1), hence every point between them (false for NaN).
  bool SegmentInside(float x, float y, float last_x, float last_y) const {
    const float w1 = static_cast<float>(width - 1), h1 = static_cast<float>(height - 1);
    return x >= 0.f && y >= 0.f && last_x >= 0.f && last_y >= 0.f && x < w1 && y < h1 &&
           last_x < w1 && last_y < h1;
  }
  // For a readable segment (or point, last = first): whether the AVX2
  // bilinear reads along it (two bytes past each sample's lower right
  // pixel) stay inside the frame: clear of the last two columns, or of the
  // last two rows.
  bool VectorReadsInside(float x, float y, float last_x, float last_y) const {
    return std::max(x, last_x) < static_cast<float>(width - 2) ||
           std::max(y, last_y) < static_cast<float>(height - 2);
  }
  // Whether every byte offset into the frame fits the AVX2 paths' 32 bits.
  bool OffsetsFit32() const { return step * static_cast<size_t>(height) < (size_t{1} << 31); }
};

// One sampled row for FindADiff's row scan: the samples x = 0, N, 2N, ...
// and the thresholds a rise between their values must pass, in the units of
// the values the kernel compares (coarse a*, or ColorTable::FastA units).
struct RowSampler {
  const uint8_t* row = nullptr;
  int row_bytes = 0;              // Bytes that may be read from `row`: 3 times the frame's width.
  int count = 0;                  // Samples on the row.
  int pixel_step = 0;             // Bytes between samples: 3 N.
  int r = 0, b = 0;               // Byte offsets of red and blue in a pixel.
  const int8_t* table = nullptr;  // ColorTable::coarse_a_table() (coarse kernels only).
  int threshold = 0;              // A rise (one step, or two from green) above this may seed.
  int step_thresh = 0;            // Each of two steps rises above this...
  int green_limit = 0;            // ...from a sample two back below this...
  int red_floor = 0;              // ...to a sample above this.
  // In dim light a rise in two steps from green may seed above this lower
  // bar instead of `threshold`: a kernel that computes the sample's
  // luminance (FastY units) applies it below dim_y_limit only, the others
  // to every sample (FindADiff's accurate test decides).
  int dim_two_step_thresh = 0;
  int dim_y_limit = 0;
};

// One profile across an edge (refine_corners.cc, EdgePoint): centred on
// `middle`, searched `half` pixels either way along `outward` (the side's
// outward unit normal), the two levels read `level_offset` either side of
// the steepest change. Its samples lie kProfileStep pixels apart, at most
// kMaxProfileSteps either side of its middle (4 px).
inline constexpr float kProfileStep = 0.5f;
inline constexpr int kMaxProfileSteps = 8;
struct ProfileSpec {
  cv::Point2d middle;
  cv::Point2d outward;
  double half = 0;
  double level_offset = 0;
};
// The edge point found on a profile, if one was.
struct ProfileEdge {
  cv::Point2d edge;
  bool found = false;
};

// Decode's grid of samples over one cell: point k = j * samples + i is
// centre + s_i du + t_j dv, with s_i and t_j = spread[i] and spread[j]
// (from -1 to 1).
struct CellGrid {
  cv::Point2d centre, du, dv;
  int samples = 0;
  std::array<double, 8> spread{};
};
// The sums of R, G and B over a cell's grid points inside the frame, and
// their number.
struct PixelSums {
  int r = 0, g = 0, b = 0, n = 0;
};

// One path's kernels.
struct Kernels {
  KernelPath path = KernelPath::kScalar;

  // FindADiff's row scan on the coarse a* table (RowSampler::table):
  // coarse[i] gets sample i's coarse a*, rises[] the samples that may seed,
  // in order; returns their number. Never null.
  int (*scan_row_coarse)(const RowSampler& s, int32_t* coarse, int* rises) = nullptr;
  // The same with a* computed (ColorTable::FastA) instead of looked up; N = 4
  // only (RowSampler::pixel_step 12). Null where the path has none.
  int (*scan_row_computed_a)(const RowSampler& s, const ColorTable::FastATables& tables,
                             int* rises) = nullptr;

  // ImageView::FirstNotClearlyAbove's steps from `first` on, eight at a
  // time, `table` the coarse a* table: returns the first step it could not
  // decide. Every step before it lies inside the frame with a coarse a*
  // above `above`. The frame's byte offsets fit in 32 bits.
  int (*first_not_clearly_above)(const PixelFrame& frame, const int8_t* table, float x, float y,
                                 float dx, float dy, int first, int last, float above) = nullptr;
  // ImageView::SampleLine of the gray (R + G + B) or the R - G channel: the
  // first multiple of eight of the n samples; returns how many it did. The
  // caller guarantees that each sample's four pixels lie inside the frame,
  // that a read of two bytes past the lower right one does too, and that
  // the frame's byte offsets fit in 32 bits.
  int (*sample_line)(const PixelFrame& frame, bool gray, float x, float y, float dx, float dy,
                     int n, float* out) = nullptr;
  // EdgePoint (refine_corners.cc) for up to eight profiles, spec[0 .. count),
  // on the gray or the R - G channel (`linear`: gray in linear light), the
  // frame's byte offsets fitting in 32 bits. Returns the lanes (bit l for
  // profile l) it left to the caller's EdgePoint; out[] of the others is set.
  unsigned (*edge_points8)(const PixelFrame& frame, bool gray, int polarity,
                           const ProfileSpec* spec, int count, float min_contrast, ProfileEdge* out,
                           bool linear) = nullptr;
  // SumCellGrid's points [0, returned) of the grid's first `count`, added
  // to *sums; the frame's byte offsets fit in 32 bits.
  int (*add_grid_points)(const PixelFrame& frame, const CellGrid& grid, int count,
                         PixelSums* sums) = nullptr;

  // Whether this CPU (and this build) can run `path`; kScalar always.
  static bool Available(KernelPath path);
  // The kernels of `path`, or of the widest path below it that is available.
  static const Kernels& ForPath(KernelPath path);
  // The kernels of the widest path this CPU has.
  static const Kernels& ForCpu();
};

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_KERNELS_H_
