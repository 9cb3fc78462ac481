// Mutation of a 400 x 20 block at the paper's settings (rate 0.10, SD 0.05).
#include <benchmark/benchmark.h>

#include "qdmeta/core/mutation.hpp"

namespace {

void BM_GaussianMutation(benchmark::State& state) {
  qdmeta::Mutation mutation(qdmeta::MutationParams{});
  qdmeta::RowMatrix g = qdmeta::RowMatrix::Constant(400, 20, 0.5f);
  qdmeta::Rng rng(1);
  for (auto _ : state) {
    mutation.apply(g, rng);
    benchmark::DoNotOptimize(g.data());
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_GaussianMutation);

void BM_DiscreteStepMutation(benchmark::State& state) {
  qdmeta::MutationParams p;
  p.kind = qdmeta::MutationKind::kDiscreteStep;
  p.rate = 0.125;
  qdmeta::Mutation mutation(p);
  qdmeta::RowMatrix g = qdmeta::RowMatrix::Constant(400, 24, 0.5f);
  qdmeta::Rng rng(1);
  for (auto _ : state) {
    mutation.apply(g, rng);
    benchmark::DoNotOptimize(g.data());
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_DiscreteStepMutation);

void BM_Normal(benchmark::State& state) {
  qdmeta::Rng rng(1);
  for (auto _ : state) benchmark::DoNotOptimize(rng.normal());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Normal);

}  // namespace
