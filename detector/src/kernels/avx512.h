// The AVX-512 kernels (kernels.h says what each does). Defined only where
// kernels.h sets CHROMATAG_HAVE_X86_KERNELS, and to be called only when the
// CPU has AVX-512 F, BW and VBMI (Kernels::ForPath). Internal.
#ifndef CHROMATAG_DETECTOR_SRC_KERNELS_AVX512_H_
#define CHROMATAG_DETECTOR_SRC_KERNELS_AVX512_H_

#include "kernels/kernels.h"

#ifdef CHROMATAG_HAVE_X86_KERNELS

#define CHROMATAG_AVX512 __attribute__((target("avx512f,avx512bw,avx512vbmi")))

namespace chromatag::internal {

// Kernels::scan_row_computed_a.
CHROMATAG_AVX512 int ScanRowComputedAAvx512(const RowSampler& s,
                                            const ColorTable::FastATables& tables, int* rises);
// The computed a* that ScanRowComputedAAvx512 compares, a[i] for each of
// the row's samples (`a` holds s.count rounded up to 32 entries), in
// ColorTable::FastA units: ColorTable::FastA is its scalar reference.
CHROMATAG_AVX512 void ComputedARowAvx512(const RowSampler& s, const ColorTable::FastATables& tables,
                                         int16_t* a);

}  // namespace chromatag::internal

#endif  // CHROMATAG_HAVE_X86_KERNELS

#endif  // CHROMATAG_DETECTOR_SRC_KERNELS_AVX512_H_
