// Rebuilding QD-Meta's archives from a full database (docs/architecture.md, "Hot paths"): 500,000 rows of 20 genes and 20 base features, K = 222 feature-maps
// with weights uniform in [-1, 1], 100 x 100 grids that keep the base features.
//   BM_RebuildOne:      one map on one thread (target: at most 30 ms).
//   BM_RebuildTen/T/R:  ten maps at once on T threads (the lambda = 10 maps of a meta-generation);
//                       s_per_map = wall time / 10. R = 1: fitness trends upwards with age, as
//                       in a real run, so rows often replace their cell's winner.
//   BM_RebuildMaps/M/T: M maps (1 or 5: not a multiple of T) at once on T threads, trend database.
//   BM_MapOnly:         the feature-map alone over the database (no insertion), one thread.
//   BM_NetworkOverDatabase/S: the network kernel over the database's feature-major rows in a
//                       rebuild's blocks, one thread, told the rows are cached (S = 0: no
//                       prefetch, what every map did before) or streamed (S = 1: prefetched
//                       ahead, what a rebuild's first map over a chunk does now). The database
//                       (its feature-major copy alone is 40 MB) does not fit in the caches, so the rows come
//                       from memory either way.
//   BM_BaselineEigen:   the "before" version: blocked Eigen float products, a scalar std::exp
//                       sigmoid, add per row; one map, one thread.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "qdmeta/meta/rebuild.hpp"

namespace {

using qdmeta::Index;
using qdmeta::Real;

constexpr Index kRows = 500'000;
constexpr Index kGenes = 20;
constexpr Index kBase = 20;

qdmeta::Database make_database(bool trend) {
  qdmeta::Database d(kRows, kGenes, kBase);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Real> genes(kGenes), base(kBase);
  for (Index i = 0; i < kRows + 1234; ++i) {  // wrapped, as in a long run
    for (Real& g : genes) g = u(rng);
    for (Real& b : base) b = u(rng);
    // With a trend, newer rows are better on average, as in a real run: a row then often
    // beats its cell's winner (in the random database it rarely does).
    const float scale = trend ? 1.0f - static_cast<float>(i) / static_cast<float>(kRows + 1234) : 1.0f;
    d.insert(genes.data(), base.data(), -400.0f * scale * u(rng));
  }
  return d;
}

const qdmeta::Database& database(bool trend = false) {
  static const qdmeta::Database random_db = make_database(false);
  if (!trend) return random_db;
  static const qdmeta::Database trend_db = make_database(true);
  return trend_db;
}

std::vector<double> random_weights(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> w(222);
  for (double& x : w) x = u(rng);
  return w;
}

qdmeta::NeuralFeatureMapShape shape() {
  qdmeta::NeuralFeatureMapShape s;
  s.inputs = kBase;
  s.outputs = 2;
  return s;
}

qdmeta::GridArchiveParams grid() {
  qdmeta::GridArchiveParams p;
  p.bins = {100, 100};
  p.solution_size = kGenes;
  p.base_feature_size = kBase;
  return p;
}

void BM_RebuildOne(benchmark::State& state) {
  const qdmeta::Database& db = database();
  const qdmeta::NeuralFeatureMap map(shape(), random_weights(7));
  qdmeta::GridArchive archive(grid());
  tbb::task_arena arena(1);
  for (auto _ : state) arena.execute([&] { qdmeta::rebuild_archive(db, map, archive); });
  state.counters["elites"] = static_cast<double>(archive.size());
  state.SetItemsProcessed(state.iterations() * db.size());
}
BENCHMARK(BM_RebuildOne)->Unit(benchmark::kMillisecond)->UseRealTime();

// `count` maps rebuilt at once on `threads` threads.
void rebuild_maps(benchmark::State& state, int count, int threads, bool trend) {
  const qdmeta::Database& db = database(trend);
  std::vector<std::unique_ptr<qdmeta::NeuralFeatureMap>> maps;
  std::vector<std::unique_ptr<qdmeta::GridArchive>> archives;
  std::vector<const qdmeta::NeuralFeatureMap*> map_ptrs;
  std::vector<qdmeta::GridArchive*> archive_ptrs;
  for (int m = 0; m < count; ++m) {
    maps.push_back(std::make_unique<qdmeta::NeuralFeatureMap>(shape(), random_weights(100 + static_cast<std::uint64_t>(m))));
    archives.push_back(std::make_unique<qdmeta::GridArchive>(grid()));
    map_ptrs.push_back(maps.back().get());
    archive_ptrs.push_back(archives.back().get());
  }
  tbb::task_arena arena(threads);
  for (auto _ : state) arena.execute([&] { qdmeta::rebuild_archives(db, map_ptrs, archive_ptrs); });
  state.counters["s_per_map"] = benchmark::Counter(
      static_cast<double>(count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(state.iterations() * db.size() * count);
}

void BM_RebuildTen(benchmark::State& state) {
  rebuild_maps(state, 10, static_cast<int>(state.range(0)), state.range(1) != 0);
}
BENCHMARK(BM_RebuildTen)->ArgNames({"threads", "trend"})->Args({1, 0})->Args({2, 0})->Args({1, 1})->Args({2, 1})->Unit(benchmark::kMillisecond)->UseRealTime();

// Map counts that do not split evenly over two threads (the lambda study's 1 and 5): the
// database ranks are split instead. Trend database.
void BM_RebuildMaps(benchmark::State& state) {
  rebuild_maps(state, static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), true);
}
BENCHMARK(BM_RebuildMaps)->ArgNames({"maps", "threads"})->Args({1, 1})->Args({1, 2})->Args({5, 1})->Args({5, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MapOnly(benchmark::State& state) {
  const qdmeta::Database& db = database();
  const qdmeta::NeuralFeatureMap map(shape(), random_weights(7));
  std::vector<Real> targets(static_cast<std::size_t>(kRows * 2));
  for (auto _ : state) {
    for (const qdmeta::DatabaseSegment& seg : db.segments())
      map.map(seg.base_features, seg.count, targets.data() + seg.first_rank * 2);
    benchmark::DoNotOptimize(targets.data());
  }
  state.SetItemsProcessed(state.iterations() * db.size());
}
BENCHMARK(BM_MapOnly)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_NetworkOverDatabase(benchmark::State& state) {
  const qdmeta::Database& db = database();
  const qdmeta::NeuralFeatureMap map(shape(), random_weights(7));
  const qdmeta::BaseRows rows = state.range(0) != 0 ? qdmeta::BaseRows::streamed : qdmeta::BaseRows::cached;
  const Index block = qdmeta::kRebuildBlockRows;
  std::vector<Real> targets(static_cast<std::size_t>(2 * block));
  for (auto _ : state) {
    for (const qdmeta::DatabaseSegment& seg : db.segments())
      for (Index first = 0; first < seg.count; first += block)
        map.map_transposed(seg.base_t + first, seg.base_t_ld, std::min(block, seg.count - first), targets.data(),
                           block, rows);
    benchmark::DoNotOptimize(targets.data());
  }
  state.SetItemsProcessed(state.iterations() * db.size());
}
BENCHMARK(BM_NetworkOverDatabase)->ArgName("streamed")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BaselineEigen(benchmark::State& state) {
  using Matrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;
  const qdmeta::Database& db = database();
  const std::vector<double> w = random_weights(7);
  Matrix w1t(kBase, 10), w2t(10, 2);
  for (Index j = 0; j < 10; ++j)
    for (Index k = 0; k < kBase; ++k) w1t(k, j) = static_cast<Real>(w[static_cast<std::size_t>(j * kBase + k)]);
  const auto b1 = static_cast<Real>(w[200]);
  for (Index t = 0; t < 2; ++t)
    for (Index j = 0; j < 10; ++j) w2t(j, t) = static_cast<Real>(w[static_cast<std::size_t>(201 + t * 10 + j)]);
  const auto b2 = static_cast<Real>(w[221]);
  const Real c1 = 30.0f / 21.0f, c2 = 30.0f / 11.0f;
  qdmeta::GridArchive archive(grid());
  const Index block = 4096;
  qdmeta::RowMatrix hidden(block, 10), target(block, 2);
  for (auto _ : state) {
    archive.clear();
    for (const qdmeta::DatabaseSegment& seg : db.segments()) {
      for (Index first = 0; first < seg.count; first += block) {
        const Index n = std::min(block, seg.count - first);
        const Eigen::Map<const qdmeta::RowMatrix> base(seg.base_row(first), n, kBase);
        hidden.topRows(n).noalias() = base * w1t;
        hidden.topRows(n) = hidden.topRows(n).unaryExpr([&](Real x) { return 1.0f / (1.0f + std::exp(-c1 * (x + b1))); });
        target.topRows(n).noalias() = hidden.topRows(n) * w2t;
        target.topRows(n) = target.topRows(n).unaryExpr([&](Real x) { return 1.0f / (1.0f + std::exp(-c2 * (x + b2))); });
        archive.add_batch({{seg.genotype(first), n, seg.genotype_size},
                           {seg.fitness + first, static_cast<std::size_t>(n)},
                           {target.data(), n, 2},
                           {seg.base_row(first), n, seg.base_feature_size},
                           {}});
      }
    }
  }
  state.counters["elites"] = static_cast<double>(archive.size());
  state.SetItemsProcessed(state.iterations() * db.size());
}
BENCHMARK(BM_BaselineEigen)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
