// QD-Meta (Algorithm 1) on a small Rastrigin: determinism at any thread count, evaluation
// accounting, the database receiving every offspring, and CMA-ES learning versus the frozen
// ablation.
#include "qdmeta/algorithms/qd_meta.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

QdMeta small_qd_meta(std::uint64_t seed, bool frozen = false, int generations = 2, bool sarsa = false) {
  RastriginParams rp;
  rp.dimensions = 6;
  QdMetaParams p;
  p.meta_population = 4;
  p.batch_size = 50;
  p.initial_population = 200;
  p.database_capacity = 3000;
  p.frozen = frozen;
  GridArchiveParams grid;
  grid.bins = {20, 20};
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  return QdMeta(p, Task(RastriginTask(rp)), std::make_unique<RastriginTranslationMeta>(mp), grid, {},
                sarsa ? std::unique_ptr<GenerationController>(std::make_unique<SarsaControl>(SarsaParams{}))
                      : std::make_unique<StaticControl>(generations),
                seed);
}

TEST(QdMeta, SameSeedSameBitsAtAnyThreadCount) {
  std::vector<EliteTable> elites;
  std::vector<std::vector<double>> fitness;
  for (int threads : {1, 2, 3}) {
    auto evaluator = make_evaluator(threads);
    QdMeta q = small_qd_meta(5);
    for (int t = 0; t < 6; ++t) q.step(*evaluator);
    elites.push_back(q.elites());
    fitness.push_back(q.meta_fitness());
  }
  for (int k : {1, 2}) {
    EXPECT_EQ(fitness[0], fitness[static_cast<std::size_t>(k)]);
    EXPECT_EQ(elites[0].objective, elites[static_cast<std::size_t>(k)].objective);
    EXPECT_TRUE(elites[0].solutions == elites[static_cast<std::size_t>(k)].solutions);
  }
}

TEST(QdMeta, CountsAndStoresEveryBottomLevelEvaluation) {
  SerialEvaluator evaluator;
  QdMeta q = small_qd_meta(2);
  q.step(evaluator);
  // 200 initial + 4 maps x 2 generations x 50.
  EXPECT_EQ(q.counters().bottom, 600);
  EXPECT_EQ(q.database().size(), 600);
  EXPECT_GT(q.counters().meta, 0);
  q.step(evaluator);
  EXPECT_EQ(q.counters().bottom, 1000);
  EXPECT_EQ(q.generation(), 2);
  ASSERT_NE(q.last_meta_record(), nullptr);
  EXPECT_EQ(q.last_meta_record()->generations, 2);
  const auto& f = q.meta_fitness();
  EXPECT_EQ(q.last_meta_record()->meta_fitness_best, *std::max_element(f.begin(), f.end()));
  for (int t = 0; t < 10; ++t) q.step(evaluator);
  EXPECT_EQ(q.database().size(), 3000);  // capacity reached: the newest 3000 are kept
}

// Mean and sample SD / sqrt(n) written out again, for the meta-population's statistics.
MeanSe by_hand(const std::vector<double>& v) {
  double mean = 0.0;
  for (double x : v) mean += x / static_cast<double>(v.size());
  double ss = 0.0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, v.size() > 1 ? std::sqrt(ss / static_cast<double>(v.size() - 1) / static_cast<double>(v.size())) : 0.0};
}

void expect_near(const MeanSe& a, const MeanSe& b, const char* what) {
  EXPECT_NEAR(a.mean, b.mean, 1e-9 * std::max(1.0, std::abs(b.mean))) << what;
  EXPECT_NEAR(a.se, b.se, 1e-9 * std::max(1.0, std::abs(b.se))) << what;
}

TEST(QdMeta, RecordsTheStatisticsOfEveryMapOfTheMetaPopulation) {
  SerialEvaluator evaluator;
  QdMeta q = small_qd_meta(4);
  for (int t = 0; t < 3; ++t) q.step(evaluator);
  const auto& archives = q.map_archives();
  ASSERT_EQ(archives.size(), 4u);
  std::vector<double> size, mean, max, qd;
  for (const GridArchive& a : archives) {
    const ArchiveStats s = a.stats();
    size.push_back(static_cast<double>(s.num_elites));
    mean.push_back(s.obj_mean);
    max.push_back(s.obj_max);
    qd.push_back(s.qd_score);
  }
  const PopulationStats& p = q.last_meta_record()->population;
  expect_near(p.num_elites, by_hand(size), "archive size");
  expect_near(p.obj_mean, by_hand(mean), "average fitness");
  expect_near(p.obj_max, by_hand(max), "global fitness");
  expect_near(p.qd_score, by_hand(qd), "QD-score");
  EXPECT_GT(p.num_elites.se, 0.0);  // four different feature-maps fill different cells
  // The logged best map is the meta-population's map of highest meta-fitness.
  const auto& f = q.meta_fitness();
  const auto best = static_cast<std::size_t>(std::max_element(f.begin(), f.end()) - f.begin());
  EXPECT_EQ(q.stats(), archives[best].stats());
}

TEST(QdMeta, BestArchiveHoldsTheTasksFunctionOfItsGenotypesAndBaseFeatures) {
  SerialEvaluator evaluator;
  QdMeta q = small_qd_meta(3);
  for (int t = 0; t < 4; ++t) q.step(evaluator);
  const EliteTable t = q.elites();
  ASSERT_GT(t.size(), 10);
  ASSERT_EQ(t.base_features.cols(), 6);
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), 6});
    EXPECT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f));
    EXPECT_TRUE(t.base_features.row(i) == t.solutions.row(i));  // Rastrigin's base features are the genotype
    for (Index j = 0; j < 2; ++j) {
      EXPECT_GE(t.measures(i, j), 0.0f);
      EXPECT_LE(t.measures(i, j), 1.0f);
    }
  }
}

TEST(QdMeta, FrozenCmaEsKeepsItsInitialDistribution) {
  SerialEvaluator evaluator;
  QdMeta q = small_qd_meta(4, /*frozen=*/true);
  const CmaEsState initial = CmaEs::initial_state(q.cma_es().params());
  for (int t = 0; t < 3; ++t) q.step(evaluator);
  EXPECT_TRUE(q.cma_es().state().mean == initial.mean);
  EXPECT_EQ(q.cma_es().state().sigma, initial.sigma);
}

TEST(QdMeta, LearningBeatsTheFrozenAblationAtEqualBudget) {
  // Paper setting of the meta level on a smaller problem: the same seed and budget, CMA-ES
  // updating versus frozen; the mean meta-fitness of the last meta-generations must be higher.
  auto last_mean = [](bool frozen) {
    auto evaluator = make_evaluator(0);
    QdMeta q = small_qd_meta(11, frozen, 1);
    double sum = 0;
    for (int t = 0; t < 120; ++t) {
      q.step(*evaluator);
      if (t >= 100) sum += q.last_meta_record()->meta_fitness_mean;
    }
    return sum / 20;
  };
  const double learned = last_mean(false), frozen = last_mean(true);
  EXPECT_GT(learned, 2.0 * frozen) << "learned " << learned << ", frozen " << frozen;
}

TEST(QdMeta, ACheckpointedRunContinuesBitIdentically) {
  // Run 8 meta-generations straight; and 4, checkpoint, load into a freshly built QD-Meta, 4
  // more. SARSA control, so the controller's tree, Q-values and traces travel too.
  SerialEvaluator evaluator;
  QdMeta straight = small_qd_meta(21, false, 2, true);
  for (int t = 0; t < 8; ++t) straight.step(evaluator);
  QdMeta first = small_qd_meta(21, false, 2, true);
  for (int t = 0; t < 4; ++t) first.step(evaluator);
  BinaryWriter out;
  first.save(out);
  QdMeta second = small_qd_meta(21, false, 2, true);
  BinaryReader in(out.bytes(), "memory");
  second.load(in);
  in.finish();
  for (int t = 0; t < 4; ++t) second.step(evaluator);
  EXPECT_EQ(second.counters(), straight.counters());
  EXPECT_EQ(second.meta_fitness(), straight.meta_fitness());
  EXPECT_TRUE(second.database() == straight.database());
  EXPECT_TRUE(second.cma_es().state() == straight.cma_es().state());
  EXPECT_EQ(second.elites().objective, straight.elites().objective);
  EXPECT_TRUE(second.elites().solutions == straight.elites().solutions);
  EXPECT_EQ(second.last_meta_record()->generations, straight.last_meta_record()->generations);
}

TEST(QdMeta, ACheckpointOfAnotherShapeIsRefused) {
  SerialEvaluator evaluator;
  QdMeta q = small_qd_meta(1);
  q.step(evaluator);
  BinaryWriter out;
  q.save(out);
  QdMeta sarsa = small_qd_meta(1, false, 2, true);  // a static controller's state will not load into SARSA
  BinaryReader in(out.bytes(), "memory");
  EXPECT_THROW(sarsa.load(in), InputError);
}

}  // namespace
}  // namespace qdmeta
