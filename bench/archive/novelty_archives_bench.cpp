// The archives pyribs users reach for after the grid: the proximity archive's novelty queries
// (a batch of 540, CMA-MAE's 15 emitters x 36, against 1,000 and 10,000 elites in 2-D) and its
// add with local competition, and the sliding-boundaries archive's add (remaps included).
#include <benchmark/benchmark.h>

#include <vector>

#include "qdmeta/archive/proximity_archive.hpp"
#include "qdmeta/archive/sliding_boundaries_archive.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

std::vector<double> uniform(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<double> v(n);
  for (double& x : v) x = rng.uniform();
  return v;
}

ProximityArchive filled_proximity(Index elites, bool local_competition) {
  ProximityArchiveParams p;
  p.solution_size = 3;
  p.measure_size = 2;
  p.k_neighbors = 15;
  p.novelty_threshold = 0.0;  // every row goes in, to fill it
  p.local_competition = local_competition;
  ProximityArchive a(p);
  const auto n = static_cast<std::size_t>(elites);
  a.add(uniform(3 * n, 1), uniform(n, 2), uniform(2 * n, 3));
  return a;
}

void BM_ProximityNovelty(benchmark::State& state) {
  const ProximityArchive archive = filled_proximity(state.range(0), false);
  const std::vector<double> queries = uniform(2 * 540, 4);
  for (auto _ : state) benchmark::DoNotOptimize(archive.novelty(queries));
  state.counters["queries/s"] = benchmark::Counter(540.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ProximityNovelty)->Arg(1'000)->Arg(10'000)->Unit(benchmark::kMillisecond);

// A batch of 540 that is never novel enough (threshold 1 in the unit square), judged by local
// competition: the archive keeps its size, elites are replaced, the k-d tree is rebuilt.
void BM_ProximityAddLocalCompetition(benchmark::State& state) {
  ProximityArchiveParams p;
  p.solution_size = 3;
  p.measure_size = 2;
  p.k_neighbors = 15;
  p.novelty_threshold = 1.0;
  p.local_competition = true;
  ProximityArchive seeded(p);
  const auto n = static_cast<std::size_t>(state.range(0));
  // Into the empty archive every row goes in (its novelty is the threshold's), so one batch seeds it.
  seeded.add(uniform(3 * n, 1), uniform(n, 2), uniform(2 * n, 3));
  std::uint64_t seed = 10;
  for (auto _ : state) {
    state.PauseTiming();
    const auto x = uniform(3 * 540, seed++), f = uniform(540, seed++), m = uniform(2 * 540, seed++);
    state.ResumeTiming();
    benchmark::DoNotOptimize(seeded.add(x, f, m));
  }
  state.counters["rows/s"] = benchmark::Counter(540.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ProximityAddLocalCompetition)->Arg(1'000)->Arg(10'000)->Unit(benchmark::kMillisecond);

// pyribs's defaults (remap every 100, buffer 1,000) on a 100 x 100 grid, batches of 540.
void BM_SlidingBoundariesAdd(benchmark::State& state) {
  SlidingBoundariesParams p;
  p.solution_size = 3;
  p.dims = {100, 100};
  p.lower_bounds = {0.0, 0.0};
  p.upper_bounds = {1.0, 1.0};
  SlidingBoundariesArchive archive(p);
  std::uint64_t seed = 10;
  for (auto _ : state) {
    state.PauseTiming();
    const auto x = uniform(3 * 540, seed++), f = uniform(540, seed++), m = uniform(2 * 540, seed++);
    state.ResumeTiming();
    benchmark::DoNotOptimize(archive.add(x, f, m));
  }
  state.counters["rows/s"] = benchmark::Counter(540.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SlidingBoundariesAdd)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace qdmeta
