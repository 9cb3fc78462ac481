// Nearest-centroid lookups (the CVT insertion hot path) and k-means: the blocked-product exact
// search against the plain loop, at 10,000 centroids in 20-D (the paper's
// Rastrigin CVT setting; target in docs/architecture.md, "Hot paths"), and in 2-D the bucket
// grid against both.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include "qdmeta/archive/kmeans.hpp"
#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/rng.hpp"

#if __has_include(<nanoflann.hpp>)
#include <nanoflann.hpp>
#define QDMETA_HAVE_NANOFLANN 1
#endif

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

// The 2-D case (a planar arm's end-effector position): 10,000 centroids from k-means over
// 100,000 uniform points in [0,1]^2 (random seeding, 10 Lloyd passes, as bench/peers makes
// them), 4,000 uniform query points, one thread. method 0: the plain loop (the definition);
// 1: the blocked product (find() in 2-D before the grid); 2: find(), the bucket grid.
const RowMatrix& centroids_2d() {
  static const RowMatrix centroids = [] {
    KMeansParams p;
    p.centroids = 10'000;
    p.samples = 100'000;
    p.init = KMeansInit::kRandom;
    p.init_samples = 100'000;
    p.iterations = 10;
    return kmeans(uniform_points(p.samples, 2, p.seed), p).centroids;
  }();
  return centroids;
}

void BM_NearestCentroid2D(benchmark::State& state) {
  const RowMatrix& centroids = centroids_2d();
  const NearestCentroid search(centroids);
  const RowMatrix points = random_block(4'000, 2, 2);
  const Index method = state.range(0);
  std::vector<Index> cells(4'000);
  for (auto _ : state) {
    if (method == 0)
      for (Index i = 0; i < 4'000; ++i) cells[static_cast<std::size_t>(i)] = nearest_centroid_naive(centroids, points.row(i).data());
    else if (method == 1)
      search.find_by_product(points.data(), 4'000, cells.data());
    else
      search.find(points.data(), 4'000, cells.data());
    benchmark::DoNotOptimize(cells.data());
  }
  state.counters["lookups/s"] = benchmark::Counter(4'000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NearestCentroid2D)->ArgName("method")->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

#ifdef QDMETA_HAVE_NANOFLANN
// The same lookups by a nanoflann k-d tree over the centroids (its nearest by its own float
// distance, ties unresolved: a lower bound on an exact search built on it).
struct CentroidCloud {
  const RowMatrix* c;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(c->rows()); }
  Real kdtree_get_pt(std::size_t i, std::size_t d) const { return (*c)(static_cast<Index>(i), static_cast<Index>(d)); }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using CentroidTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, CentroidCloud>, CentroidCloud, 2, std::uint32_t>;

void BM_NearestCentroid2DNanoflann(benchmark::State& state) {
  const CentroidCloud cloud{&centroids_2d()};
  CentroidTree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const RowMatrix points = random_block(4'000, 2, 2);
  std::vector<Index> cells(4'000);
  for (auto _ : state) {
    for (Index i = 0; i < 4'000; ++i) {
      std::uint32_t index = 0;
      Real distance = 0;
      tree.knnSearch(points.row(i).data(), 1, &index, &distance);
      cells[static_cast<std::size_t>(i)] = index;
    }
    benchmark::DoNotOptimize(cells.data());
  }
  state.counters["lookups/s"] = benchmark::Counter(4'000.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NearestCentroid2DNanoflann)->Unit(benchmark::kMicrosecond);
#endif

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
