// The machine's float multiply-add peak, the floor of every kernel that is mostly multiply-adds
// (the map rebuild's network: 220 per database row). Ten independent chains of fused multiply-adds
// on 256-bit (8 floats) or 128-bit (4 floats) vectors, enough to hide the latency; the figure is
// vector FMA instructions per second, all threads together. With ->Threads(2) it shows whether
// two logical CPUs have FMA units of their own (the total doubles) or share one core's (it stays).
#include <benchmark/benchmark.h>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>

namespace {

template <typename Vec, Vec (*Set1)(float), Vec (*Fmadd)(Vec, Vec, Vec)>
void fma_chains(benchmark::State& state) {
  constexpr int kChains = 10;
  constexpr long kSteps = 1 << 16;
  Vec acc[kChains];
  for (int i = 0; i < kChains; ++i) acc[i] = Set1(1.0f + 1e-3f * static_cast<float>(i));
  const Vec m = Set1(0.9999999f), c = Set1(1e-7f);
  for (auto _ : state) {
    for (long s = 0; s < kSteps; ++s)
      for (int i = 0; i < kChains; ++i) acc[i] = Fmadd(acc[i], m, c);
    for (int i = 0; i < kChains; ++i) benchmark::DoNotOptimize(acc[i]);
  }
  state.SetItemsProcessed(state.iterations() * kSteps * kChains);
}

__m256 set1_256(float x) { return _mm256_set1_ps(x); }
__m256 fmadd_256(__m256 a, __m256 b, __m256 c) { return _mm256_fmadd_ps(a, b, c); }
__m128 set1_128(float x) { return _mm_set1_ps(x); }
__m128 fmadd_128(__m128 a, __m128 b, __m128 c) { return _mm_fmadd_ps(a, b, c); }

void BM_Fma256(benchmark::State& state) { fma_chains<__m256, set1_256, fmadd_256>(state); }
void BM_Fma128(benchmark::State& state) { fma_chains<__m128, set1_128, fmadd_128>(state); }
BENCHMARK(BM_Fma256)->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK(BM_Fma128)->Threads(1)->Threads(2)->UseRealTime();

}  // namespace
#endif
