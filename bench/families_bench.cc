// Micro-benchmarks of the families layer: code lookup and colour conversion.
#include <benchmark/benchmark.h>

#include <random>

#include "chromatag/families/color.h"
#include "chromatag/families/decoder.h"

namespace chromatag {
namespace {

void BM_DecodeLookup(benchmark::State& state, const char* name) {
  auto family = TagFamily::Load(name);
  auto decoder = CodeDecoder::Create(family, CodeDecoder::DefaultRadius(*family));
  std::mt19937_64 rng(1);
  std::vector<Code> observed(4096);
  for (auto& code : observed) {
    const int id = family->kept_ids()[rng() % family->kept_ids().size()];
    code = family->Rotate(family->CodeOf(id), static_cast<int>(rng() % 4)) ^
           (Code{1} << (rng() % family->num_bits()));
  }
  size_t i = 0;
  for (auto _ : state) {
    CodeMatch match;
    benchmark::DoNotOptimize(decoder->Decode(observed[i++ & 4095], &match));
  }
}
BENCHMARK_CAPTURE(BM_DecodeLookup, 16h5, "16h5");
BENCHMARK_CAPTURE(BM_DecodeLookup, 36h11, "36h11");

void BM_DecoderBuild(benchmark::State& state, const char* name) {
  auto family = TagFamily::Load(name);
  for (auto _ : state) {
    benchmark::DoNotOptimize(CodeDecoder::Create(family, CodeDecoder::DefaultRadius(*family)));
  }
}
BENCHMARK_CAPTURE(BM_DecoderBuild, 16h5, "16h5")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DecoderBuild, 36h11, "36h11")->Unit(benchmark::kMillisecond);

// The exact formula, for scale: the detector converts with its compact
// ColorTable (detector/src/kernels/color_table.h) instead.
void BM_SrgbToLabExact(benchmark::State& state) {
  uint8_t v = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        SrgbToLab(Rgb8{v, static_cast<uint8_t>(v * 3), static_cast<uint8_t>(v * 7)}));
    ++v;
  }
}
BENCHMARK(BM_SrgbToLabExact);

}  // namespace
}  // namespace chromatag

BENCHMARK_MAIN();
