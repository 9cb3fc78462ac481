// Rastrigin meta-fitnesses on a full 100 x 100 archive (10,000 elites, N = 20): one evaluate()
// scores a 10% sample (n = 1,000). Also the pairwise-distance sum alone, and the straightforward
// double-precision reference (scalar rastrigin:: functions, per pair distances) for comparison.
#include <benchmark/benchmark.h>

#include <cmath>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace {

using qdmeta::Index;

qdmeta::RowMatrix random_archive(Index rows, Index cols) {
  qdmeta::Rng rng(42);
  qdmeta::RowMatrix g(rows, cols);
  for (Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<float>(rng.uniform());
  return g;
}

const qdmeta::RowMatrix& archive() {
  static const qdmeta::RowMatrix a = random_archive(10000, 20);
  return a;
}

std::vector<int> dims() {
  qdmeta::Rng rng(7);
  return qdmeta::rastrigin::sample_dimensions(rng, 20, 10);
}

void BM_DimensionMeta(benchmark::State& state) {
  const qdmeta::RastriginDimensionMeta meta({}, dims());
  qdmeta::SerialEvaluator ev;
  qdmeta::Rng rng(1);
  for (auto _ : state) benchmark::DoNotOptimize(meta.evaluate(archive(), rng, ev));
  state.SetItemsProcessed(state.iterations() * 1000);  // sampled solutions
}
BENCHMARK(BM_DimensionMeta)->Unit(benchmark::kMicrosecond);

void BM_TranslationMeta(benchmark::State& state) {
  qdmeta::RastriginMetaParams p;
  p.transform_per_solution = state.range(0) != 0;
  const qdmeta::RastriginTranslationMeta meta(p);
  qdmeta::SerialEvaluator ev;
  qdmeta::Rng rng(1);
  for (auto _ : state) benchmark::DoNotOptimize(meta.evaluate(archive(), rng, ev));
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(BM_TranslationMeta)->ArgName("per_solution")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_PairwiseDistanceSum(benchmark::State& state) {
  const auto n = static_cast<Index>(state.range(0));
  const qdmeta::RowMatrix p = archive().topRows(n);
  for (auto _ : state) benchmark::DoNotOptimize(qdmeta::pairwise_distance_sum(p));
  state.SetItemsProcessed(state.iterations() * n * (n - 1) / 2);  // pairs
}
BENCHMARK(BM_PairwiseDistanceSum)->Arg(1000)->Arg(4096)->Unit(benchmark::kMicrosecond);

// The plain loops that give the same bits (the kernel before the vector steps).
void BM_PairwiseDistanceSumPortable(benchmark::State& state) {
  const auto n = static_cast<Index>(state.range(0));
  const qdmeta::RowMatrix p = archive().topRows(n);
  for (auto _ : state) benchmark::DoNotOptimize(qdmeta::pairwise_distance_sum_portable(p));
  state.SetItemsProcessed(state.iterations() * n * (n - 1) / 2);
}
BENCHMARK(BM_PairwiseDistanceSumPortable)->Arg(1000)->Unit(benchmark::kMicrosecond);

// The straightforward computation: scalar double Rastrigin per (solution, task), distances pair by pair.
void BM_DimensionReference(benchmark::State& state) {
  const auto j = dims();
  const auto& a = archive();
  qdmeta::Rng rng(1);
  for (auto _ : state) {
    const auto sample = qdmeta::sample_elites(a.rows(), 1000, rng);
    double q = 0.0, d = 0.0;
    for (int dim : j)
      for (Index s : sample) q += qdmeta::rastrigin::score(qdmeta::rastrigin::without_dimension({a.row(s).data(), 20}, dim));
    for (std::size_t s = 0; s < sample.size(); ++s)
      for (std::size_t t = s + 1; t < sample.size(); ++t)
        d += (a.row(sample[s]).cast<double>() - a.row(sample[t]).cast<double>()).norm();
    benchmark::DoNotOptimize(q + d);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(BM_DimensionReference)->Unit(benchmark::kMicrosecond);

void BM_TranslationReference(benchmark::State& state) {
  const auto& a = archive();
  qdmeta::Rng rng(1);
  for (auto _ : state) {
    const auto sample = qdmeta::sample_elites(a.rows(), 1000, rng);
    const auto transforms = qdmeta::rastrigin::sample_meta_transforms(rng, 2);
    double q = 0.0;
    for (const auto& t : transforms)
      for (Index s : sample) {
        const auto f = qdmeta::rastrigin::translated({a.row(s).data(), 20}, t.a, t.b);
        q += f ? qdmeta::rastrigin::score(*f) : 0.0;
      }
    benchmark::DoNotOptimize(q);
  }
  state.SetItemsProcessed(state.iterations() * 1000);
}
BENCHMARK(BM_TranslationReference)->Unit(benchmark::kMicrosecond);

}  // namespace
