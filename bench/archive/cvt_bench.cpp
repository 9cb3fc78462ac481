// Nearest-centroid lookups (the CVT insertion hot path) and k-means: the blocked-product exact
// search against the plain loop, at 10,000 centroids in 20-D (the paper's
// Rastrigin CVT setting; target in docs/architecture.md, "Hot paths").
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "qdmeta/archive/kmeans.hpp"
#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

RowMatrix random_block(Index rows, Index cols, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix m(rows, cols);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<Real>(rng.uniform());
  return m;
}

// Lookups of a batch of 400 offspring-like points among 10,000 centroids, one thread; the
// argument is the number of points per find() call (the CVT loop's parallel chunk).
void BM_NearestCentroidBlocked(benchmark::State& state) {
  const NearestCentroid search(random_block(10'000, 20, 1));
  const RowMatrix points = random_block(400, 20, 2);
  const Index chunk = state.range(0);
  std::vector<Index> cells(400);
  for (auto _ : state) {
    for (Index first = 0; first < 400; first += chunk)
      search.find(points.row(first).data(), std::min(chunk, 400 - first), cells.data() + first);
    benchmark::DoNotOptimize(cells.data());
  }
  state.counters["lookups/s"] = benchmark::Counter(400.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NearestCentroidBlocked)->Arg(1)->Arg(25)->Arg(50)->Arg(100)->Arg(400)->Unit(benchmark::kMillisecond);

void BM_NearestCentroidNaive(benchmark::State& state) {
  const RowMatrix centroids = random_block(10'000, 20, 1);
  const RowMatrix points = random_block(400, 20, 2);
  std::vector<Index> cells(400);
  for (auto _ : state) {
    for (Index i = 0; i < 400; ++i) cells[static_cast<std::size_t>(i)] = nearest_centroid_naive(centroids, points.row(i).data());
    benchmark::DoNotOptimize(cells.data());
  }
  state.counters["lookups/s"] = benchmark::Counter(400.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NearestCentroidNaive)->Unit(benchmark::kMillisecond);

// Neighbour lists (a CVT elite's 256 nearest centroids and the bound on the rest), the remake of
// the parent-bound search: 64 points, made `rows` at a time (1: one per call; 8: the centroids
// streamed once per 8 points). items_per_second = lists per second.
void BM_NeighbourLists(benchmark::State& state) {
  const NearestCentroid search(random_block(10'000, 20, 1));
  const RowMatrix points = random_block(64, 20, 2);
  const Index rows = state.range(0), length = 256;
  std::vector<std::int32_t> cells(64 * length);
  std::vector<float> distances(cells.size());
  std::vector<double> outside(64);
  for (auto _ : state) {
    for (Index first = 0; first < 64; first += rows) {
      if (rows == 1)  // the one-point call (main's only form: this case also builds against it)
        search.neighbours(points.row(first).data(), length, cells.data() + first * length, distances.data() + first * length,
                          outside.data() + first);
      else
        search.neighbours(points.row(first).data(), rows, length, cells.data() + first * length,
                          distances.data() + first * length, outside.data() + first);
    }
    benchmark::DoNotOptimize(cells.data());
  }
  state.SetItemsProcessed(64 * state.iterations());
}
BENCHMARK(BM_NeighbourLists)->ArgName("rows")->Arg(1)->Arg(8)->Unit(benchmark::kMicrosecond);

// k-means++ seeding and Lloyd iterations on a reduced case (1,000 centroids over 100,000 20-D
// points); the full 10,000 x 1,000,000 case is timed as a whole run (bench/README.md).
void BM_KMeans(benchmark::State& state) {
  const RowMatrix points = uniform_points(100'000, 20, 1);
  KMeansParams p;
  p.centroids = 1'000;
  p.init_samples = 100'000;
  p.iterations = static_cast<int>(state.range(1));
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    KMeansResult r;
    arena.execute([&] { r = kmeans(points, p); });
    benchmark::DoNotOptimize(r.centroids.data());
  }
}
BENCHMARK(BM_KMeans)->ArgNames({"threads", "iterations"})->Args({1, 0})->Args({1, 3})->Args({2, 3})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace qdmeta
