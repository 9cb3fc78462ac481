// Whole-run benchmark: CVT-MAP-Elites on 20-D Rastrigin with the paper's 10,000 centroids (read
// from the centroid cache: run configs/rastrigin/cvt-map-elites.toml once to make them), batch
// 400, 500,000 evaluations from an empty archive, brute-force or parent-bound search, 1 or 2
// threads. items_per_second = evaluations per second; `searched` = share of offspring whose cell
// needed the full search.
#include <benchmark/benchmark.h>

#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/assembly/cvt_centroids.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/io/centroid_cache.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace {

// The paper's centroids from the centroid cache, as a run takes them; false when not there yet.
bool use_cached_centroids(qdmeta::CvtMapElitesParams& p) {
  qdmeta::CvtCentroidSettings cached;
  cached.cache_dir = qdmeta::default_centroid_cache_dir();
  if (cached.cache_dir.empty() ||
      !std::filesystem::exists(cached.cache_dir / (qdmeta::centroid_cache_key(20, p.kmeans) + ".bin")))
    return false;
  p.make_centroids = qdmeta::cvt_centroid_source(cached, p.kmeans, qdmeta::Task{qdmeta::RastriginTask{}});
  return true;
}

// Times runs of `budget` evaluations from an empty archive (its centroids made before the
// timing): items_per_second is evaluations per second.
void time_runs(benchmark::State& state, const qdmeta::CvtMapElitesParams& p, const qdmeta::RastriginParams& task,
               const qdmeta::MutationParams& mutation, int threads, std::int64_t budget) {
  auto evaluator = qdmeta::make_evaluator(threads);
  for (auto _ : state) {
    state.PauseTiming();
    qdmeta::CvtMapElites cvt(p, qdmeta::Task{qdmeta::RastriginTask{task}}, mutation, 1);
    cvt.prepare(*evaluator);
    state.ResumeTiming();
    while (cvt.counters().bottom < budget) cvt.step(*evaluator);
    state.counters["num_elites"] = static_cast<double>(cvt.archive().size());
    state.counters["searched"] = static_cast<double>(cvt.searched()) / static_cast<double>(cvt.counters().bottom);
  }
  state.SetItemsProcessed(state.iterations() * budget);
}

void BM_CvtMapElitesRastrigin(benchmark::State& state) {
  const auto search = static_cast<qdmeta::CvtSearch>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const std::int64_t budget = 500'000;
  qdmeta::CvtMapElitesParams p;
  p.search = search;
  if (!use_cached_centroids(p)) {
    state.SkipWithError("no cached centroids: run configs/rastrigin/cvt-map-elites.toml once");
    return;
  }
  time_runs(state, p, {}, {}, threads, budget);
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

// The same loop with 2-D descriptors (Rastrigin in 2-D: the genes are the descriptor, both
// mutated for every offspring), 10,000 centroids from k-means over 100,000 uniform points
// (random seeding, 10 Lloyd passes: bench/peers's settings; made before the timing), 500,000
// evaluations, 1 thread. search 0: parent-bound (lists, the bucket grid as the full search);
// 1: brute-force, what auto picks in 2-D (the bucket grid for every offspring).
void BM_CvtMapElites2D(benchmark::State& state) {
  qdmeta::CvtMapElitesParams p;
  p.search = static_cast<qdmeta::CvtSearch>(state.range(0));
  p.kmeans.samples = 100'000;
  p.kmeans.init = qdmeta::KMeansInit::kRandom;
  p.kmeans.init_samples = 100'000;
  qdmeta::RastriginParams task;
  task.dimensions = 2;
  qdmeta::MutationParams mutation;
  mutation.rate = 1.0;
  time_runs(state, p, task, mutation, 1, 500'000);
}
BENCHMARK(BM_CvtMapElites2D)
    ->ArgName("search")  // 0: parent-bound, 1: brute-force (auto in 2-D)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);

// Insertion lookups alone, in a realistic state: an archive after 2,000,000 evaluations of the
// run above, and batches of offspring made from it as the run makes them. Each lookup is exact;
// parent-bound settles most from the parent's neighbour list, brute-force searches all 10,000
// centroids (blocked float product). Threads split each batch into chunks of 50, as the run does.
void BM_CvtLookups(benchmark::State& state) {
  const auto search = static_cast<qdmeta::CvtSearch>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  qdmeta::CvtMapElitesParams p;
  if (!use_cached_centroids(p)) {
    state.SkipWithError("no cached centroids: run configs/rastrigin/cvt-map-elites.toml once");
    return;
  }
  auto evaluator = qdmeta::make_evaluator(2);
  qdmeta::CvtMapElites cvt(p, qdmeta::Task{qdmeta::RastriginTask{}}, {}, 1);
  while (cvt.counters().bottom < 2'000'000) cvt.step(*evaluator);
  const qdmeta::CvtArchive& archive = cvt.archive();
  // 50 batches of 400 offspring; Rastrigin's descriptor is the genotype itself.
  const qdmeta::Mutation mutation({});
  std::vector<qdmeta::RowMatrix> batches(50, qdmeta::RowMatrix(400, 20));
  std::vector<std::vector<qdmeta::Index>> parents(50);
  for (std::size_t b = 0; b < batches.size(); ++b) {
    qdmeta::Rng rng(b);
    qdmeta::generate_offspring(archive, mutation, rng, batches[b], &parents[b]);
  }
  std::vector<qdmeta::Index> cells(400);
  tbb::task_arena arena(threads);
  std::int64_t searched = 0, lookups = 0;
  for (auto _ : state) {
    for (std::size_t b = 0; b < batches.size(); ++b) {
      const qdmeta::Index* from = search == qdmeta::CvtSearch::kParentBound ? parents[b].data() : nullptr;
      std::atomic<std::int64_t> n{0};
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<qdmeta::Index>(0, 8, 1), [&](const tbb::blocked_range<qdmeta::Index>& r) {
          for (qdmeta::Index c = r.begin(); c < r.end(); ++c)
            n += archive.locate(batches[b].row(c * 50).data(), 50, from ? from + c * 50 : nullptr, cells.data() + c * 50);
        });
      });
      searched += n;
      lookups += 400;
    }
  }
  state.counters["lookups/s"] = benchmark::Counter(static_cast<double>(lookups), benchmark::Counter::kIsRate);
  state.counters["searched"] = static_cast<double>(searched) / static_cast<double>(lookups);
  state.counters["num_elites"] = static_cast<double>(archive.size());
}
BENCHMARK(BM_CvtLookups)
    ->ArgNames({"search", "threads"})  // search 0: parent-bound, 1: brute-force
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({0, 2})
    ->Args({1, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(1.0);

}  // namespace
