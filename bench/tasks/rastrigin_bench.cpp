// Rastrigin evaluation throughput: the vectorised float batch path, the Task wrapper around
// it (with its output checks), and the double-precision reference for comparison.
#include <benchmark/benchmark.h>

#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace {

qdmeta::RowMatrix random_block(qdmeta::Index rows, qdmeta::Index cols) {
  qdmeta::Rng rng(42);
  qdmeta::RowMatrix g(rows, cols);
  for (qdmeta::Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<float>(rng.uniform());
  return g;
}

void BM_RastriginBatch(benchmark::State& state) {
  const auto g = random_block(400, 20);
  qdmeta::Vector f(400);
  std::vector<float> scratch;
  for (auto _ : state) {
    qdmeta::rastrigin::evaluate_batch(g.data(), 400, 20, f.data(), scratch);
    benchmark::DoNotOptimize(f.data());
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_RastriginBatch);

void BM_RastriginTask(benchmark::State& state) {
  const auto g = random_block(400, 20);
  qdmeta::Task task{qdmeta::RastriginTask{}};
  qdmeta::EvaluationBatch out;
  out.resize(400, 20);
  for (auto _ : state) {
    task.evaluate({g.data(), 400, 20}, out.view());
    benchmark::DoNotOptimize(out.fitness.data());
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_RastriginTask);

void BM_RastriginReferenceDouble(benchmark::State& state) {
  const auto g = random_block(400, 20);
  for (auto _ : state) {
    double sum = 0;
    for (qdmeta::Index r = 0; r < 400; ++r) sum += qdmeta::rastrigin::standard({g.row(r).data(), 20});
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_RastriginReferenceDouble);

}  // namespace
