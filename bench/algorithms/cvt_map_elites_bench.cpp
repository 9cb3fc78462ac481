// Whole-run benchmark: CVT-MAP-Elites on 20-D Rastrigin with the paper's 10,000 centroids (read
// from the centroid cache: run configs/rastrigin/cvt-map-elites.toml once to make them), batch
// 400, 500,000 evaluations from an empty archive, brute-force or parent-bound search, 1 or 2
// threads. items_per_second = evaluations per second; `searched` = share of offspring whose cell
// needed the full search.
#include <benchmark/benchmark.h>

#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace {

void BM_CvtMapElitesRastrigin(benchmark::State& state) {
  const auto search = static_cast<qdmeta::CvtSearch>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const std::int64_t budget = 500'000;
  qdmeta::CvtMapElitesParams p;
  p.search = search;
  p.cache_dir = qdmeta::default_centroid_cache_dir();
  if (p.cache_dir.empty() || !std::filesystem::exists(p.cache_dir / (qdmeta::centroid_cache_key(20, p.kmeans) + ".bin"))) {
    state.SkipWithError("no cached centroids: run configs/rastrigin/cvt-map-elites.toml once");
    return;
  }
  auto evaluator = qdmeta::make_evaluator(threads);
  for (auto _ : state) {
    state.PauseTiming();
    qdmeta::CvtMapElites cvt(p, qdmeta::Task{qdmeta::RastriginTask{}}, {}, 1);
    cvt.prepare(*evaluator);
    state.ResumeTiming();
    while (cvt.counters().bottom < budget) cvt.step(*evaluator);
    state.counters["num_elites"] = static_cast<double>(cvt.archive().size());
    state.counters["searched"] = static_cast<double>(cvt.searched()) / static_cast<double>(cvt.counters().bottom);
  }
  state.SetItemsProcessed(state.iterations() * budget);
}
BENCHMARK(BM_CvtMapElitesRastrigin)
    ->ArgNames({"search", "threads"})  // search 0: parent-bound, 1: brute-force
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
