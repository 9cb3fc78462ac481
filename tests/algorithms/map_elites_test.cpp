// MAP-Elites: determinism at any thread count, invariants of the archive, stored values equal
// to the task's function, evaluation accounting, and a known optimum.
#include "qdmeta/algorithms/map_elites.hpp"

#include <gtest/gtest.h>

#include "expect_same_elites.hpp"

#include <atomic>
#include <cmath>
#include <map>

#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

MapElites map_elites_on_rastrigin(std::uint64_t seed, int dimensions = 20) {
  RastriginParams rp;
  rp.dimensions = dimensions;
  return MapElites({}, Task(RastriginTask(rp)), std::make_unique<SelectFeatureMap>(dimensions, std::vector<int>{0, 1}),
                   {}, {}, seed);
}

TEST(MapElites, SameSeedSameBitsAtAnyThreadCount) {
  std::vector<EliteTable> results;
  for (int threads : {1, 2, 3}) {
    auto evaluator = make_evaluator(threads);
    MapElites me = map_elites_on_rastrigin(7);
    for (int g = 0; g < 60; ++g) me.step(*evaluator);
    results.push_back(me.elites());
  }
  expect_same_elites(results[0], results[1]);
  expect_same_elites(results[0], results[2]);
}

TEST(MapElites, DifferentSeedsGiveDifferentArchives) {
  SerialEvaluator evaluator;
  MapElites a = map_elites_on_rastrigin(1), b = map_elites_on_rastrigin(2);
  for (int g = 0; g < 5; ++g) {
    a.step(evaluator);
    b.step(evaluator);
  }
  EXPECT_NE(a.elites().objective, b.elites().objective);
}

TEST(MapElites, CountsInitialPopulationThenBatches) {
  SerialEvaluator evaluator;
  MapElites me = map_elites_on_rastrigin(3);
  me.step(evaluator);
  EXPECT_EQ(me.counters().bottom, 2000);
  EXPECT_EQ(me.counters().meta, 0);
  me.step(evaluator);
  me.step(evaluator);
  EXPECT_EQ(me.counters().bottom, 2800);
  EXPECT_EQ(me.generation(), 3);
}

TEST(MapElites, ArchiveNeverLosesItsBestNorShrinks) {
  SerialEvaluator evaluator;
  MapElites me = map_elites_on_rastrigin(11);
  me.step(evaluator);
  std::vector<Real> previous(static_cast<std::size_t>(me.archive().cells()), -INFINITY);
  double best = -INFINITY;
  Index size = 0;
  for (int g = 0; g < 200; ++g) {
    me.step(evaluator);
    const ArchiveStats s = me.stats();
    EXPECT_GE(s.obj_max, best);
    EXPECT_GE(s.num_elites, size);
    best = s.obj_max;
    size = s.num_elites;
    for (Index c : me.archive().filled_cells()) {
      EXPECT_GE(me.archive().objective(c), previous[static_cast<std::size_t>(c)]);
      previous[static_cast<std::size_t>(c)] = me.archive().objective(c);
    }
  }
}

TEST(MapElites, StoredValuesAreTheTasksFunctionOfTheStoredGenotype) {
  SerialEvaluator evaluator;
  MapElites me = map_elites_on_rastrigin(5);
  for (int g = 0; g < 100; ++g) me.step(evaluator);
  const EliteTable t = me.elites();
  ASSERT_GT(t.size(), 3000);
  for (Index i = 0; i < t.size(); ++i) {
    const double expected = rastrigin::standard({t.solutions.row(i).data(), 20});
    EXPECT_NEAR(t.objective[static_cast<std::size_t>(i)], expected, 1e-3 + 1e-5 * std::abs(expected));
    EXPECT_EQ(t.measures(i, 0), t.solutions(i, 0));
    EXPECT_EQ(t.measures(i, 1), t.solutions(i, 1));
    EXPECT_EQ(t.index[static_cast<std::size_t>(i)], me.archive().index_of(t.measures.row(i).data()));
    for (Index j = 0; j < 20; ++j) {
      EXPECT_GE(t.solutions(i, j), 0.0f);
      EXPECT_LE(t.solutions(i, j), 1.0f);
    }
  }
}

TEST(MapElites, FindsTheKnownOptimumOfTwoDimensionalRastrigin) {
  // With 2 genes both used as measures, the cell holding g = (0.5, 0.5) spans |x| <= 0.0512,
  // where f >= -(2 * 0.0512^2 + 20 (1 - cos(2 pi 0.0512))) = -1.03; the global optimum is 0.
  SerialEvaluator evaluator;
  MapElites me = map_elites_on_rastrigin(9, 2);
  while (me.counters().bottom < 200'000) me.step(evaluator);
  EXPECT_GT(me.stats().obj_max, -1.1);
  EXPECT_LE(me.stats().obj_max, 0.0);
  // With 2 genes and rate 0.1, 81% of offspring are unmutated copies: coverage is still high.
  EXPECT_GT(me.stats().num_elites, 9000);
}

// Rows whose first gene is below 0.5 are "dead".
struct DeadBelowHalfTask {
  Index genotype_size() const { return 3; }
  Index base_feature_size() const { return 3; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    for (Index i = 0; i < g.count; ++i) {
      out.fitness[i] = g.row(i)[2];
      std::copy_n(g.row(i), 3, out.base_row(i));
      out.valid[i] = g.row(i)[0] >= 0.5f;
    }
  }
};

TEST(MapElites, InvalidSolutionsNeverEnterTheArchive) {
  SerialEvaluator evaluator;
  MapElites me({}, Task(DeadBelowHalfTask{}), std::make_unique<SelectFeatureMap>(3, std::vector<int>{0, 1}), {}, {}, 4);
  for (int g = 0; g < 20; ++g) me.step(evaluator);
  const EliteTable t = me.elites();
  ASSERT_GT(t.size(), 0);
  for (Index i = 0; i < t.size(); ++i) EXPECT_GE(t.solutions(i, 0), 0.5f);
}

struct AllDeadTask {
  Index genotype_size() const { return 2; }
  Index base_feature_size() const { return 2; }
  void evaluate(GenotypeView g, EvaluationView out) const {
    for (Index i = 0; i < g.count; ++i) {
      out.fitness[i] = 0;
      std::copy_n(g.row(i), 2, out.base_row(i));
      out.valid[i] = 0;
    }
  }
};

TEST(MapElites, KeepsDrawingRandomGenotypesWhileTheArchiveIsEmpty) {
  SerialEvaluator evaluator;
  MapElites me({}, Task(AllDeadTask{}), std::make_unique<SelectFeatureMap>(2, std::vector<int>{0, 1}), {}, {}, 4);
  me.step(evaluator);
  me.step(evaluator);
  EXPECT_EQ(me.archive().size(), 0);
  EXPECT_EQ(me.counters().bottom, 2400);
}

// Counts how many distinct instances evaluated: a task that may not be shared must be
// cloned per worker, and the clones must give the same results.
std::atomic<int> g_unshared_copies{0};
struct UnsharedTask {
  UnsharedTask() = default;
  UnsharedTask(const UnsharedTask&) { ++g_unshared_copies; }
  Index genotype_size() const { return 20; }
  Index base_feature_size() const { return 20; }
  bool shareable() const { return false; }
  void evaluate(GenotypeView g, EvaluationView out) const { RastriginTask{}.evaluate(g, out); }
};

TEST(MapElites, UnshareableTaskIsClonedPerWorkerWithIdenticalResults) {
  auto threaded = make_thread_evaluator(2, 16);
  SerialEvaluator serial;
  auto build = [] {
    return MapElites({}, Task(UnsharedTask{}), std::make_unique<SelectFeatureMap>(20, std::vector<int>{0, 1}), {}, {}, 2);
  };
  MapElites a = build(), b = build();
  g_unshared_copies = 0;
  for (int g = 0; g < 10; ++g) {
    a.step(*threaded);
    b.step(serial);
  }
  EXPECT_GE(g_unshared_copies.load(), 1);
  EXPECT_LE(g_unshared_copies.load(), 2 * threaded->workers());  // kept across batches, not per batch
  expect_same_elites(a.elites(), b.elites());
}

TEST(MapElites, RejectsAFeatureMapOfTheWrongSize) {
  EXPECT_THROW(MapElites({}, Task(RastriginTask{}), std::make_unique<SelectFeatureMap>(20, std::vector<int>{0, 1, 2}),
                         {}, {}, 1),
               InputError);
  RastriginParams rp;
  rp.dimensions = 5;
  EXPECT_THROW(MapElites({}, Task(RastriginTask(rp)), std::make_unique<SelectFeatureMap>(20, std::vector<int>{0, 1}),
                         {}, {}, 1),
               InputError);
}

TEST(MapElites, ACheckpointedRunContinuesBitIdentically) {
  SerialEvaluator evaluator;
  MapElites straight = map_elites_on_rastrigin(8);
  for (int g = 0; g < 30; ++g) straight.step(evaluator);
  MapElites first = map_elites_on_rastrigin(8);
  for (int g = 0; g < 12; ++g) first.step(evaluator);
  BinaryWriter out;
  first.save(out);
  MapElites second = map_elites_on_rastrigin(8);
  BinaryReader in(out.bytes(), "memory");
  second.load(in);
  in.finish();
  expect_same_elites(second.elites(), first.elites());
  // The fill order matters too: parents are drawn by position in it.
  EXPECT_EQ(second.archive().filled_cells(), first.archive().filled_cells());
  for (int g = 12; g < 30; ++g) second.step(evaluator);
  EXPECT_EQ(second.counters(), straight.counters());
  EXPECT_EQ(second.generation(), straight.generation());
  expect_same_elites(second.elites(), straight.elites());
}

// A warm start: the given archive's elites are the first generation's parents (a batch of
// mutants, no random initial population), none of them is lost, and an archive can be given only
// before the first step.
TEST(MapElites, StartFromGivenArchiveMutatesItsElitesFirst) {
  SerialEvaluator evaluator;
  MapElites donor = map_elites_on_rastrigin(5);
  for (int g = 0; g < 10; ++g) donor.step(evaluator);
  const EliteTable given = donor.elites();
  MapElites warm = map_elites_on_rastrigin(6);
  warm.start_from(donor.archive());
  expect_same_elites(warm.elites(), given);
  warm.step(evaluator);
  EXPECT_EQ(warm.counters().bottom, 400);  // one batch of mutants, not the 2,000 random genotypes
  EXPECT_GE(warm.archive().size(), donor.archive().size());
  // Every cell of the given archive is still filled, at least as well as it was given.
  const EliteTable after = warm.elites();
  std::map<std::int64_t, Real> best_after;
  for (std::size_t i = 0; i < after.index.size(); ++i) best_after[after.index[i]] = after.objective[i];
  for (std::size_t i = 0; i < given.index.size(); ++i) {
    ASSERT_TRUE(best_after.count(given.index[i])) << given.index[i];
    EXPECT_GE(best_after[given.index[i]], given.objective[i]) << given.index[i];
  }
  EXPECT_THROW(warm.start_from(donor.archive()), Error);
}

TEST(MapElites, ACheckpointOfAnotherTaskSizeIsRefused) {
  SerialEvaluator evaluator;
  MapElites small = map_elites_on_rastrigin(1, 5);
  small.step(evaluator);
  BinaryWriter out;
  small.save(out);
  MapElites big = map_elites_on_rastrigin(1, 20);
  BinaryReader in(out.bytes(), "memory");
  try {
    big.load(in);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not fit this run's archive"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace qdmeta
