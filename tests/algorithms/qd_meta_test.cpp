// QD-Meta (Algorithm 1) on a small Rastrigin: determinism at any thread count, evaluation
// accounting, the database receiving every offspring, and CMA-ES learning versus the frozen
// ablation.
#include "qdmeta/algorithms/qd_meta.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <any>
#include <cmath>
#include <memory>
#include <mutex>
#include <numeric>
#include <set>

#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "small_qd_meta.hpp"

namespace qdmeta {
namespace {

QdMeta small_qd_meta(std::uint64_t seed, bool frozen = false, int generations = 2, bool sarsa = false,
                     std::unique_ptr<MetaObjective> objective = nullptr) {
  QdMetaParams p = small_qd_meta_params();
  p.frozen = frozen;
  return small_qd_meta_of(p, seed,
                          sarsa ? std::unique_ptr<GenerationController>(std::make_unique<SarsaControl>(SarsaParams{}))
                                : std::make_unique<StaticControl>(generations),
                          std::move(objective));
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

// Keeps a copy of every archive it is handed and scores it by the mean fitness the archive stored.
class StoredFitnessMeta final : public MetaObjective {
 public:
  struct Seen {
    RowMatrix genotypes;
    Vector fitness;
    RowMatrix measures;
    RowMatrix base_features;
  };
  std::string name() const override { return "stored-fitness"; }
  MetaPlan plan(const MetaArchive& archive, Rng&) const override {
    const std::lock_guard lock(*mutex_);  // maps are scored in parallel
    seen->push_back({archive.genotypes(), archive.fitness(), archive.measures(), archive.base_features()});
    return {{}, static_cast<double>(archive.fitness().cast<double>().mean())};
  }
  MetaFitnessResult score(const MetaArchive&, const MetaPlan& plan, std::span<const EvaluationBatch>) const override {
    return {std::any_cast<double>(plan.state), 0};
  }
  std::shared_ptr<std::vector<Seen>> seen = std::make_shared<std::vector<Seen>>();

 private:
  std::shared_ptr<std::mutex> mutex_ = std::make_shared<std::mutex>();
};

TEST(QdMeta, TheMetaObjectiveReadsWhatEachArchiveStored) {
  auto objective = std::make_unique<StoredFitnessMeta>();
  const auto seen = objective->seen;
  QdMeta q = small_qd_meta(4, false, 2, false, std::move(objective));
  q.step(*make_evaluator(2));
  ASSERT_EQ(seen->size(), 4u);  // one archive per map
  GridArchiveParams cells_of;
  cells_of.bins = {20, 20};
  cells_of.solution_size = 6;
  const GridArchive grid(cells_of);
  std::vector<double> means;
  for (const StoredFitnessMeta::Seen& s : *seen) {
    const Index k = s.genotypes.rows();
    ASSERT_GT(k, 10);
    ASSERT_EQ(s.fitness.size(), k);
    ASSERT_EQ(s.measures.rows(), k);
    ASSERT_EQ(s.measures.cols(), 2);
    // The stored fitness and base features are the task's for those genotypes, exactly.
    EvaluationBatch again;
    again.resize(k, 6);
    RastriginParams six;
    six.dimensions = 6;
    RastriginTask(six).evaluate({s.genotypes.data(), k, 6}, again.view());
    EXPECT_TRUE(s.fitness == again.fitness);
    EXPECT_TRUE(s.base_features == again.base_features);
    // The measures are the archive's cells: in [0, 1], one elite in each.
    std::set<Index> cells;
    for (Index r = 0; r < k; ++r) cells.insert(grid.index_of(s.measures.row(r).data()));
    EXPECT_EQ(static_cast<Index>(cells.size()), k);
    EXPECT_GE(s.measures.minCoeff(), 0.0f);
    EXPECT_LE(s.measures.maxCoeff(), 1.0f);
    means.push_back(static_cast<double>(s.fitness.cast<double>().mean()));
  }
  // Each map's meta-fitness is what the objective computed from its stored fitness.
  std::vector<double> recorded = q.meta_fitness();
  std::sort(means.begin(), means.end());
  std::sort(recorded.begin(), recorded.end());
  EXPECT_EQ(means, recorded);
}

TEST(MetaArchive, GenotypesAloneHaveNoStoredValuesAndMismatchedRowsAreRefused) {
  const RowMatrix genotypes = RowMatrix::Constant(3, 2, 0.5f);
  const MetaArchive alone = genotypes;
  EXPECT_EQ(alone.size(), 3);
  EXPECT_EQ(&alone.genotypes(), &genotypes);
  EXPECT_FALSE(alone.has_stored());
  EXPECT_THROW(
      {
        try {
          (void)alone.fitness();
        } catch (const Error& e) {
          EXPECT_STREQ(e.what(), "MetaArchive: this archive holds genotypes only, no fitness (QD-Meta's archives hold them)");
          throw;
        }
      },
      Error);
  EXPECT_THROW((void)alone.measures(), Error);
  EXPECT_THROW((void)alone.base_features(), Error);
  const Vector fitness = Vector::Zero(3), short_fitness = Vector::Zero(2);
  const RowMatrix measures(3, 2), base(3, 4);
  const MetaArchive whole(genotypes, fitness, measures, base);
  EXPECT_TRUE(whole.has_stored());
  EXPECT_EQ(&whole.fitness(), &fitness);
  EXPECT_EQ(whole.base_features().cols(), 4);
  EXPECT_THROW((void)MetaArchive(genotypes, short_fitness, measures, base), Error);
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
