// The detector's vector kernels and their one dispatch point. Internal.
//
// A kernel is the inner loop of a stage written for one instruction set:
// kernels/avx2.cc and kernels/avx512.cc hold them, kernels/scalar.* the
// scalar loops they must match to the last bit (and fall back to in their
// tails). The stages never test the CPU themselves: a Detector picks one
// Kernels at creation (ForCpu) and every stage reaches it through its
// ImageView. Tests build a view with ForPath to run a given path.
//
// A null pointer means the path has no vector version of that kernel: the
// caller runs its scalar loop.
//
// The vector kernels are compiled for their instruction set function by
// function (target attributes), so that a portable build (CHROMATAG_NATIVE
// off) runs anywhere and takes them where the CPU has them.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_KERNELS_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_KERNELS_H_

#include <array>
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "kernels/color_table.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define CHROMATAG_HAVE_X86_KERNELS 1
#endif

namespace chromatag::internal {

class ImageView;
struct ChannelWeights;
struct ProfileSpec;
struct ProfileEdge;
struct PixelSums;

// The instruction sets, narrowest first. kAvx512 is AVX-512 with byte and
// word lanes and byte permutes (F, BW, VBMI); its kernels that need no
// more than AVX2 are the AVX2 ones.
enum class KernelPath { kScalar, kAvx2, kAvx512 };

// One sampled row for FindADiff's row scan: the samples x = 0, N, 2N, ...
// and the thresholds a rise between their values must pass, in the units of
// the values the kernel compares (coarse a*, or ColorTable::FastA units).
struct RowSampler {
  const uint8_t* row;
  int row_bytes;        // Bytes that may be read from `row`: 3 times the frame's width.
  int count;            // Samples on the row.
  int pixel_step;       // Bytes between samples: 3 N.
  int r, b;             // Byte offsets of red and blue in a pixel.
  const int8_t* table;  // ColorTable::coarse_a_table() (coarse kernels only).
  int threshold;        // A rise (one step, or two from green) above this may seed.
  int step_thresh;      // Each of two steps rises above this...
  int green_limit;      // ...from a sample two back below this...
  int red_floor;        // ...to a sample above this.
};

// Decode's grid of samples over one cell: point k = j * samples + i is
// centre + s_i du + t_j dv, with s_i and t_j = spread[i] and spread[j]
// (from -1 to 1).
struct CellGrid {
  cv::Point2d centre, du, dv;
  int samples = 0;
  std::array<double, 8> spread{};
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
  // time: returns the first step it could not decide. Every step before it
  // lies inside the frame with a coarse a* above `above`. The frame's byte
  // offsets fit in 32 bits.
  int (*first_not_clearly_above)(const uint8_t* data, size_t step, int width, int height,
                                 int r_offset, const int8_t* table, float x, float y, float dx,
                                 float dy, int first, int last, float above) = nullptr;
  // ImageView::SampleLine of the gray (R + G + B) or the R - G channel: the
  // first multiple of eight of the n samples; returns how many it did. The
  // caller guarantees that each sample's four pixels lie inside the frame,
  // that a read of two bytes past the lower right one does too, and that
  // the frame's byte offsets fit in 32 bits.
  int (*sample_line)(const uint8_t* data, size_t step, int r_offset, bool gray, float x, float y,
                     float dx, float dy, int n, float* out) = nullptr;
  // EdgePoint (refine_corners.cc) for up to eight profiles, spec[0 .. count),
  // on the gray or the R - G channel (`linear`: gray in linear light), the
  // frame's byte offsets fitting in 32 bits. Returns the lanes (bit l for
  // profile l) it left to the caller's EdgePoint; out[] of the others is set.
  unsigned (*edge_points8)(const ImageView& image, const ChannelWeights& channel, int polarity,
                           const ProfileSpec* spec, int count, float min_contrast, ProfileEdge* out,
                           bool linear) = nullptr;
  // SumCellGrid's points [0, returned) of the grid's first `count`, added
  // to *sums; the frame's byte offsets fit in 32 bits.
  int (*add_grid_points)(const ImageView& image, const CellGrid& grid, int count,
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
