// The iso+line operator in the algorithms: the order of the draws behind each offspring (two
// elites, then the variation), and MAP-Elites, CVT-MAP-Elites and QD-Meta with it giving the
// same bits at any thread count; and MAP-Elites with a variation function of the caller's.
#include <gtest/gtest.h>

#include "expect_same_elites.hpp"
#include "mutation_params.hpp"

#include <vector>

#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

// MAP-Elites's offspring of a grid archive: per row its parent cell, its second parent cell
// (drawn independently, uniformly over the filled cells), then the row's variation.
TEST(IsoLine, GridOffspringDrawTwoElitesPerRowInOrder) {
  GridArchiveParams gp;
  gp.bins = {10};
  gp.solution_size = 3;
  GridArchive archive(gp);
  for (int c = 0; c < 10; c += 3) {
    const Real x = static_cast<Real>(c) / 10;
    const std::vector<Real> solution = {x, 1 - x, 0.5f}, measure = {x + 0.05f};
    archive.add(solution, 1.0f, measure);
  }
  ASSERT_EQ(archive.size(), 4);
  const Mutation m(iso_line(0.05, 0.5));
  RowMatrix offspring(64, 3);
  std::vector<Index> parents;
  Rng rng(9), expect_rng(9);
  generate_offspring(archive, m, rng, offspring, &parents);
  ASSERT_EQ(parents.size(), 64u);
  for (Index r = 0; r < 64; ++r) {
    const Index cell = archive.sample_cell(expect_rng), other = archive.sample_cell(expect_rng);
    std::vector<Real> child(archive.solution(cell), archive.solution(cell) + 3);
    m.apply_iso_line(child.data(), archive.solution(other), 3, expect_rng);
    EXPECT_EQ(parents[static_cast<std::size_t>(r)], cell);
    for (Index k = 0; k < 3; ++k) EXPECT_EQ(offspring(r, k), child[static_cast<std::size_t>(k)]) << r << "," << k;
  }
  EXPECT_EQ(rng.state(), expect_rng.state());
}

// AURORA's path (any selection through pick_parent): the same order, parent then second parent.
TEST(IsoLine, MutateCopiesDrawsTwoParentsPerRow) {
  const std::vector<std::vector<Real>> table = {{0.1f, 0.2f}, {0.8f, 0.3f}, {0.5f, 0.9f}};
  auto pick = [&](Rng& r) { return table[r.below(table.size())].data(); };
  const Mutation m(iso_line(0.02, 0.3));
  RowMatrix offspring(20, 2);
  Rng rng(4), expect_rng(4);
  mutate_copies(pick, m, rng, offspring);
  for (Index r = 0; r < 20; ++r) {
    const Real* a = pick(expect_rng);
    std::vector<Real> child(a, a + 2);
    m.apply_iso_line(child.data(), pick(expect_rng), 2, expect_rng);
    EXPECT_EQ(offspring(r, 0), child[0]);
    EXPECT_EQ(offspring(r, 1), child[1]);
  }
}

MapElites rastrigin_map_elites(std::uint64_t seed, MutationParams mutation, int dimensions = 20) {
  RastriginParams rp;
  rp.dimensions = dimensions;
  return MapElites({}, Task(RastriginTask(rp)), std::make_unique<SelectFeatureMap>(dimensions, std::vector<int>{0, 1}),
                   {}, mutation, seed);
}

TEST(IsoLine, MapElitesSameBitsAtAnyThreadCount) {
  std::vector<EliteTable> results;
  for (int threads : {1, 3}) {
    auto evaluator = make_evaluator(threads);
    MapElites me = rastrigin_map_elites(7, iso_line());
    for (int g = 0; g < 40; ++g) me.step(*evaluator);
    results.push_back(me.elites());
  }
  expect_same_elites(results[0], results[1]);
  // And the operator is the one in use: Gaussian mutation from the same seed differs.
  SerialEvaluator serial;
  MapElites gaussian = rastrigin_map_elites(7, {});
  for (int g = 0; g < 40; ++g) gaussian.step(serial);
  EXPECT_NE(gaussian.elites().objective, results[0].objective);
}

// A caller's variation sees two elites of the archive per offspring; its offspring are the
// ones evaluated; a run with it gives the same bits at any thread count.
TEST(VariationFunction, MapElitesTakesItsOffspringFromTheFunction) {
  std::vector<EliteTable> results;
  for (int threads : {1, 3}) {
    auto evaluator = make_evaluator(threads);
    MapElites me = rastrigin_map_elites(3, {});
    int calls = 0;
    me.set_variation([&](const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed, RowMatrix& out) {
      ++calls;
      const EliteTable elites = me.elites();
      auto is_elite = [&](const RowMatrix& rows, Index r) {
        for (Index e = 0; e < elites.size(); ++e)
          if (elites.solutions.row(e) == rows.row(r)) return true;
        return false;
      };
      ASSERT_EQ(parents.rows(), out.rows());
      for (Index r = 0; r < out.rows(); r += 37) {
        EXPECT_TRUE(is_elite(parents, r)) << r;
        EXPECT_TRUE(is_elite(partners, r)) << r;
      }
      Rng rng(seed);
      const Mutation iso(iso_line());
      out = parents;
      for (Index r = 0; r < out.rows(); ++r) iso.apply_iso_line(out.row(r).data(), partners.row(r).data(), out.cols(), rng);
    });
    for (int g = 0; g < 20; ++g) me.step(*evaluator);
    EXPECT_EQ(calls, 19);  // every generation but the random first
    results.push_back(me.elites());
  }
  expect_same_elites(results[0], results[1]);
  SerialEvaluator serial;
  MapElites plain = rastrigin_map_elites(3, {});
  for (int g = 0; g < 20; ++g) plain.step(serial);
  EXPECT_NE(plain.elites().objective, results[0].objective);
}

CvtMapElites rastrigin_cvt(std::uint64_t seed, CvtSearch search) {
  CvtMapElitesParams p;
  p.search = search;
  p.neighbours = 32;
  p.kmeans.centroids = 300;
  p.kmeans.samples = 6000;
  p.kmeans.init_samples = 3000;
  p.kmeans.iterations = 3;
  p.lookup_chunk = 30;
  return CvtMapElites(p, Task(RastriginTask()), iso_line(), seed);
}

// The recorded parent (x_i) only guides the parent-bound search; the cells are exact either way.
TEST(IsoLine, CvtMapElitesSameBitsAtAnyThreadCountAndSearch) {
  std::vector<EliteTable> results;
  for (int threads : {1, 3}) {
    auto evaluator = make_evaluator(threads);
    CvtMapElites cvt = rastrigin_cvt(9, CvtSearch::kParentBound);
    for (int g = 0; g < 30; ++g) cvt.step(*evaluator);
    results.push_back(cvt.elites());
  }
  SerialEvaluator serial;
  CvtMapElites brute = rastrigin_cvt(9, CvtSearch::kBruteForce);
  for (int g = 0; g < 30; ++g) brute.step(serial);
  expect_same_elites(results[0], results[1]);
  expect_same_elites(results[0], brute.elites());
}

QdMeta rastrigin_qd_meta(std::uint64_t seed, MutationParams mutation = iso_line()) {
  RastriginParams rp;
  rp.dimensions = 6;
  QdMetaParams p;
  p.meta_population = 4;
  p.batch_size = 50;
  p.initial_population = 200;
  p.database_capacity = 3000;
  GridArchiveParams grid;
  grid.bins = {20, 20};
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  return QdMeta(p, Task(RastriginTask(rp)), std::make_unique<RastriginTranslationMeta>(mp), grid, mutation,
                std::make_unique<StaticControl>(2), seed);
}

TEST(IsoLine, QdMetaInnerLoopSameBitsAtAnyThreadCount) {
  std::vector<EliteTable> elites;
  std::vector<std::vector<double>> fitness;
  for (int threads : {1, 3}) {
    auto evaluator = make_evaluator(threads);
    QdMeta q = rastrigin_qd_meta(5);
    for (int t = 0; t < 6; ++t) q.step(*evaluator);
    elites.push_back(q.elites());
    fitness.push_back(q.meta_fitness());
  }
  expect_same_elites(elites[0], elites[1]);
  EXPECT_EQ(fitness[0], fitness[1]);
  SerialEvaluator serial;
  QdMeta gaussian = rastrigin_qd_meta(5, {});
  for (int t = 0; t < 6; ++t) gaussian.step(serial);
  EXPECT_NE(gaussian.meta_fitness(), fitness[0]);
}

}  // namespace
}  // namespace qdmeta
