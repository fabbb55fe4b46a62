// The AVX2 kernels (kernels.h says what each does). Defined only where
// kernels.h sets CHROMATAG_HAVE_X86_KERNELS, and to be called only when the
// CPU has AVX2 (Kernels::ForPath). Internal.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_AVX2_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_AVX2_H_

#include "kernels/kernels.h"

#ifdef CHROMATAG_HAVE_X86_KERNELS

#define CHROMATAG_AVX2 __attribute__((target("avx2")))

namespace chromatag::internal {

CHROMATAG_AVX2 int ScanRowCoarseAvx2(const RowSampler& s, int32_t* coarse, int* rises);
CHROMATAG_AVX2 int FirstNotClearlyAboveAvx2(const PixelFrame& frame, const int8_t* table, float x,
                                            float y, float dx, float dy, int first, int last,
                                            float above);
CHROMATAG_AVX2 int SampleLineAvx2(const PixelFrame& frame, bool gray, float x, float y, float dx,
                                  float dy, int n, float* out);
CHROMATAG_AVX2 unsigned EdgePoints8Avx2(const PixelFrame& frame, bool gray, int polarity,
                                        const ProfileSpec* spec, int count, float min_contrast,
                                        ProfileEdge* out, bool linear);
CHROMATAG_AVX2 int AddGridPointsAvx2(const PixelFrame& frame, const CellGrid& grid, int count,
                                     PixelSums* sums);

}  // namespace chromatag::internal

#endif  // CHROMATAG_HAVE_X86_KERNELS

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_AVX2_H_
