// The one place that asks which instructions the CPU has (kernels.h).
#include "kernels/kernels.h"

#include "kernels/avx2.h"
#include "kernels/avx512.h"
#include "kernels/scalar.h"

namespace chromatag::internal {
namespace {

Kernels MakeKernels(KernelPath path) {
  Kernels k;
  k.path = path;
  k.scan_row_coarse = ScanRowCoarseScalar;
#ifdef CHROMATAG_HAVE_X86_KERNELS
  if (path >= KernelPath::kAvx2) {
    k.scan_row_coarse = ScanRowCoarseAvx2;
    k.first_not_clearly_above = FirstNotClearlyAboveAvx2;
    k.sample_line = SampleLineAvx2;
    k.edge_points8 = EdgePoints8Avx2;
    k.add_grid_points = AddGridPointsAvx2;
  }
  if (path >= KernelPath::kAvx512) k.scan_row_computed_a = ScanRowComputedAAvx512;
#endif
  return k;
}

}  // namespace

bool Kernels::Available(KernelPath path) {
#ifdef CHROMATAG_HAVE_X86_KERNELS
  switch (path) {
    case KernelPath::kAvx512: {
      static const bool has = __builtin_cpu_supports("avx512f") &&
                              __builtin_cpu_supports("avx512bw") &&
                              __builtin_cpu_supports("avx512vbmi");
      return has;
    }
    case KernelPath::kAvx2: {
      static const bool has = __builtin_cpu_supports("avx2");
      return has;
    }
    case KernelPath::kScalar:
      return true;
  }
  return false;
#else
  return path == KernelPath::kScalar;
#endif
}

const Kernels& Kernels::ForPath(KernelPath path) {
  static const Kernels kScalar = MakeKernels(KernelPath::kScalar);
  static const Kernels kAvx2 = MakeKernels(KernelPath::kAvx2);
  static const Kernels kAvx512 = MakeKernels(KernelPath::kAvx512);
  if (path == KernelPath::kAvx512 && Available(KernelPath::kAvx512)) return kAvx512;
  if (path >= KernelPath::kAvx2 && Available(KernelPath::kAvx2)) return kAvx2;
  return kScalar;
}

const Kernels& Kernels::ForCpu() { return ForPath(KernelPath::kAvx512); }

}  // namespace chromatag::internal
