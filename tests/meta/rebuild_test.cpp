#include "qdmeta/meta/rebuild.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

constexpr Index kGenes = 6;
constexpr Index kBase = 5;

// A wrapped database (two segments, neither a multiple of the rebuild block) whose fitness
// values repeat, so ties (kept: first come) and improvements both occur.
Database random_database(Index capacity, Index inserts, std::uint64_t seed) {
  Database db(capacity, kGenes, kBase);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Real> genes(kGenes), base(kBase);
  for (Index i = 0; i < inserts; ++i) {
    for (Real& g : genes) g = u(rng);
    for (Real& b : base) b = u(rng);
    db.insert(genes.data(), base.data(), std::floor(u(rng) * 50.0f));
  }
  return db;
}

NeuralFeatureMap random_map(Index outputs, std::uint64_t seed) {
  NeuralFeatureMapShape s;
  s.inputs = kBase;
  s.hidden = 10;
  s.outputs = outputs;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> w(static_cast<std::size_t>(s.weight_count()));
  for (double& x : w) x = u(rng);
  return NeuralFeatureMap(s, w);
}

GridArchiveParams grid(std::vector<int> bins, Index keep_base) {
  GridArchiveParams p;
  p.bins = std::move(bins);
  p.solution_size = kGenes;
  p.base_feature_size = keep_base;
  return p;
}

// The plain definition: clear, then map and add the rows one by one, oldest first.
void sequential_reference(const Database& db, const NeuralFeatureMap& map, GridArchive& archive) {
  archive.clear();
  std::vector<Real> target(static_cast<std::size_t>(map.output_size()));
  for (Index rank = 0; rank < db.size(); ++rank) {
    map.map(db.base_features(rank), 1, target.data());
    const auto keep = static_cast<std::size_t>(archive.base_feature_size());
    archive.add({db.genotype(rank), static_cast<std::size_t>(db.genotype_size())}, db.fitness(rank), target,
                {db.base_features(rank), keep});
  }
}

void expect_same_archive(const GridArchive& got, const GridArchive& want) {
  ASSERT_EQ(got.cells(), want.cells());
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(got.filled_cells(), want.filled_cells());  // same cells, first filled in the same order
  const Index dims = want.dimensions();
  const Index genes = want.params().solution_size;
  const Index base = want.params().base_feature_size;
  for (Index c = 0; c < want.cells(); ++c) {
    ASSERT_EQ(got.occupied(c), want.occupied(c)) << "cell " << c;
    if (!want.occupied(c)) continue;
    ASSERT_EQ(got.objective(c), want.objective(c)) << "cell " << c;
    for (Index k = 0; k < genes; ++k) ASSERT_EQ(got.solution(c)[k], want.solution(c)[k]) << "cell " << c;
    for (Index k = 0; k < dims; ++k) ASSERT_EQ(got.measures(c)[k], want.measures(c)[k]) << "cell " << c;
    for (Index k = 0; k < base; ++k) ASSERT_EQ(got.base_features(c)[k], want.base_features(c)[k]) << "cell " << c;
  }
}

TEST(Rebuild, SingleMapEqualsRowByRowInsertion) {
  const Database db = random_database(3000, 7777, 1);  // wrapped: 2 segments
  ASSERT_EQ(db.segments().size(), 2);
  const NeuralFeatureMap map = random_map(2, 2);
  GridArchive got(grid({30, 30}, kBase));
  GridArchive want(grid({30, 30}, kBase));
  rebuild_archive(db, map, got);
  sequential_reference(db, map, want);
  EXPECT_GT(want.size(), 50);
  expect_same_archive(got, want);
}

TEST(Rebuild, ManyMapsEqualRowByRowWhateverTheThreadCount) {
  const Database db = random_database(2500, 4100, 3);
  std::vector<NeuralFeatureMap> maps;
  std::vector<GridArchive> want;
  for (int m = 0; m < 7; ++m) {
    // Mixed shapes: 2-D and 3-D grids, with and without base features kept.
    const Index outputs = m % 3 == 2 ? 3 : 2;
    maps.push_back(random_map(outputs, 10 + static_cast<std::uint64_t>(m)));
    want.emplace_back(grid(outputs == 3 ? std::vector<int>{8, 8, 8} : std::vector<int>{25, 25}, m % 2 ? 0 : kBase));
    sequential_reference(db, maps.back(), want.back());
  }
  for (int threads : {1, 2, 3, 4, 8}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    std::vector<GridArchive> got;
    for (const GridArchive& a : want) got.emplace_back(a.params());
    // Stale content must go: the rebuild starts from empty archives.
    const Real junk_genes[kGenes] = {};
    const Real junk_measures[3] = {0.5f, 0.5f, 0.5f};
    const std::vector<Real> junk_base(static_cast<std::size_t>(kBase), 0.5f);
    for (GridArchive& a : got)
      a.add(junk_genes, 1e9f, {junk_measures, static_cast<std::size_t>(a.dimensions())},
            {junk_base.data(), static_cast<std::size_t>(a.base_feature_size())});
    std::vector<const NeuralFeatureMap*> map_ptrs;
    std::vector<GridArchive*> archive_ptrs;
    for (std::size_t m = 0; m < maps.size(); ++m) {
      map_ptrs.push_back(&maps[m]);
      archive_ptrs.push_back(&got[m]);
    }
    tbb::task_arena arena(threads);
    arena.execute([&] { rebuild_archives(db, map_ptrs, archive_ptrs); });
    for (std::size_t m = 0; m < maps.size(); ++m) {
      SCOPED_TRACE("map " + std::to_string(m));
      expect_same_archive(got[m], want[m]);
    }
  }
}

TEST(Rebuild, OneMapSplitOverThreadsByRankEqualsRowByRow) {
  // One map on 2, 3 and 5 threads: the database ranks are split, the slices' winners merged.
  const Database db = random_database(3000, 7777, 4);  // wrapped, with ties
  const NeuralFeatureMap map = random_map(2, 6);
  GridArchive want(grid({30, 30}, kBase));
  sequential_reference(db, map, want);
  for (int threads : {1, 2, 3, 5}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    GridArchive got(grid({30, 30}, kBase));
    const NeuralFeatureMap* maps[] = {&map};
    GridArchive* archives[] = {&got};
    tbb::task_arena arena(threads);
    arena.execute([&] { rebuild_archives(db, maps, archives); });
    expect_same_archive(got, want);
  }
}

TEST(Rebuild, PartiallyFilledAndEmptyDatabases) {
  const NeuralFeatureMap map = random_map(2, 5);
  for (Index inserts : {0, 1, 511, 512, 513, 1500}) {
    SCOPED_TRACE(std::to_string(inserts) + " rows");
    const Database db = random_database(2000, inserts, 6);
    GridArchive got(grid({10, 10}, kBase));
    GridArchive want(grid({10, 10}, kBase));
    const Real genes[kGenes] = {};
    const Real measures[2] = {0.1f, 0.9f};
    const Real base[kBase] = {};
    got.add(genes, 1.0f, measures, base);
    const NeuralFeatureMap* maps[] = {&map};
    GridArchive* archives[] = {&got};
    rebuild_archives(db, maps, archives);
    sequential_reference(db, map, want);
    expect_same_archive(got, want);
  }
}

TEST(Rebuild, ChecksSizes) {
  const Database db = random_database(100, 50, 7);
  const NeuralFeatureMap map = random_map(2, 8);
  GridArchive a(grid({10, 10}, kBase));
  GridArchive b(grid({10, 10}, kBase));
  const NeuralFeatureMap* two_maps[] = {&map, &map};
  GridArchive* one_archive[] = {&a};
  GridArchive* same_twice[] = {&a, &a};
  GridArchive* with_null[] = {&a, nullptr};
  auto expect_message = [](auto&& call, const std::string& message) {
    try {
      call();
      ADD_FAILURE() << "no InputError, expected: " << message;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), message);
    }
  };
  expect_message([&] { rebuild_archives(db, two_maps, one_archive); }, "rebuild: 2 feature-maps but 1 archives");
  expect_message([&] { rebuild_archives(db, two_maps, same_twice); }, "rebuild: archives 0 and 1 are the same");
  expect_message([&] { rebuild_archives(db, two_maps, with_null); }, "rebuild: archive 1 is null");
  GridArchive three_d(grid({4, 4, 4}, kBase));
  expect_message([&] { rebuild_archive(db, map, three_d); },
                 "rebuild: feature-map 0 gives 2 target features but archive 0 has 3 dimensions");
  GridArchiveParams p = grid({10, 10}, kBase);
  p.solution_size = kGenes + 1;
  GridArchive wrong_genes(p);
  expect_message([&] { rebuild_archive(db, map, wrong_genes); },
                 "rebuild: archive 0 stores solutions of 7 genes but the database stores 6");
  GridArchive wrong_base(grid({10, 10}, 3));
  expect_message([&] { rebuild_archive(db, map, wrong_base); },
                 "rebuild: archive 0 keeps 3 base features but the database stores 5");
  NeuralFeatureMapShape s;
  s.inputs = 4;
  s.outputs = 2;
  const NeuralFeatureMap narrow(s, std::vector<double>(static_cast<std::size_t>(s.weight_count()), 0.0));
  expect_message([&] { rebuild_archive(db, narrow, b); },
                 "rebuild: feature-map 0 reads 4 base features but the database stores 5");
}

}  // namespace
}  // namespace qdmeta
