// Whole-run benchmark: plain MAP-Elites on 20-D Rastrigin, 100 x 100 grid, batch 400,
// 1,000,000 evaluations, with 1 and 2 threads. items_per_second = evaluations per second.
#include <benchmark/benchmark.h>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace {

void BM_MapElitesRastrigin(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const std::int64_t budget = 1'000'000;
  auto evaluator = qdmeta::make_evaluator(threads);
  for (auto _ : state) {
    qdmeta::Task task{qdmeta::RastriginTask{}};
    qdmeta::MapElites me({}, task, std::make_unique<qdmeta::SelectFeatureMap>(20, std::vector<int>{0, 1}), {}, {}, 1);
    while (me.counters().bottom < budget) me.step(*evaluator);
    state.counters["num_elites"] = static_cast<double>(me.archive().size());
  }
  state.SetItemsProcessed(state.iterations() * budget);
}
BENCHMARK(BM_MapElitesRastrigin)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
