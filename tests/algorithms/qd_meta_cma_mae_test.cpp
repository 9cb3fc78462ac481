// QD-Meta over CMA-MAE (qd_meta.bottom_level = "cma-mae", algorithms/qd_meta_emitters.hpp) on the
// small Rastrigin of the QD-Meta tests: each map's emitters start over its rebuilt archive
// (thresholds at its elites, first means drawn from them); the run gives the same bits at any
// thread count and across a checkpoint, feeds the database every evaluation, and fills its maps
// better than random search of the same budget.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/algorithms/qd_meta_emitters.hpp"
#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/meta/rebuild.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "resumed_run.hpp"
#include "small_qd_meta.hpp"

namespace qdmeta {
namespace {

// 5 emitters of 10 rows: a generation of 50 rows per map, as small_qd_meta_params()'s batch.
QdMetaParams qd_meta_cma_mae_params() {
  QdMetaParams p = small_qd_meta_params();
  p.bottom_level = BottomLevel::kCmaMae;
  p.emitters.emitters = 5;
  p.emitters.emitter.batch_size = 10;
  p.emitters.emitter.x0.assign(6, 0.5);
  p.emitters.emitter.sigma0 = 0.1;
  p.emitters.emitter.ranker = EmitterRanker::kImprovement;
  p.emitters.emitter.selection = EmitterSelection::kMu;
  p.emitters.emitter.restart = EmitterRestart::kBasic;
  p.emitters.emitter.bounds = CmaBoundsHandling::kResample;
  p.emitters.thresholds = {0.01, -2000.0};
  return p;
}

QdMeta rastrigin_qd_meta_of(const QdMetaParams& p, std::uint64_t seed, int dims) {
  RastriginParams rp;
  rp.dimensions = dims;
  GridArchiveParams grid;
  grid.bins = {20, 20};
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  return QdMeta(p, Task(RastriginTask(rp)), std::make_unique<RastriginTranslationMeta>(mp), grid, {},
                std::make_unique<StaticControl>(3), seed);
}

QdMeta small_cma_mae_qd_meta(std::uint64_t seed, bool sarsa = false) {
  return small_qd_meta_of(qd_meta_cma_mae_params(), seed,
                          sarsa ? std::unique_ptr<GenerationController>(std::make_unique<SarsaControl>(SarsaParams{}))
                                : std::make_unique<StaticControl>(3));
}

void expect_same_run(const QdMeta& a, const QdMeta& b) {
  EXPECT_EQ(a.counters(), b.counters());
  EXPECT_EQ(a.meta_fitness(), b.meta_fitness());
  EXPECT_TRUE(a.database() == b.database());
  EXPECT_TRUE(a.cma_es().state() == b.cma_es().state());
  EXPECT_EQ(a.elites().objective, b.elites().objective);
  EXPECT_TRUE(a.elites().solutions == b.elites().solutions);
}

TEST(QdMetaCmaMae, SameSeedSameBitsAtAnyThreadCount) {
  std::vector<QdMeta> runs;
  runs.reserve(3);
  for (int threads : {1, 2, 3}) {
    auto evaluator = make_evaluator(threads);
    runs.push_back(small_cma_mae_qd_meta(5));
    for (int t = 0; t < 5; ++t) runs.back().step(*evaluator);
  }
  expect_same_run(runs[0], runs[1]);
  expect_same_run(runs[0], runs[2]);
  // And the run is not the Gaussian one's (the emitters made its offspring).
  SerialEvaluator serial;
  QdMeta gaussian = small_qd_meta_of(small_qd_meta_params(), 5, std::make_unique<StaticControl>(3));
  for (int t = 0; t < 5; ++t) gaussian.step(serial);
  EXPECT_EQ(gaussian.counters().bottom, runs[0].counters().bottom);
  EXPECT_FALSE(gaussian.database() == runs[0].database());
}

TEST(QdMetaCmaMae, TheDatabaseReceivesEveryEvaluationTheLastBatchesNewest) {
  SerialEvaluator evaluator;
  QdMeta q = small_cma_mae_qd_meta(2);
  // 200 initial, then per meta-generation 4 maps x 3 generations x 5 emitters x 10 rows.
  for (std::int64_t steps = 1; steps <= 2; ++steps) {
    q.step(evaluator);
    for (std::int64_t n : {q.counters().bottom, std::int64_t{q.database().size()}, q.database().total_inserted()})
      EXPECT_EQ(n, 200 + 600 * steps);
  }
  // Map by map, oldest first: the newest 50 rows are the last map's last batch, as its emitters asked it.
  const Scheduler<GridArchive>* last = q.emitters(3);
  ASSERT_NE(last, nullptr);
  const RowMatrix& batch = last->solutions();
  ASSERT_EQ(batch.rows(), 50);
  for (Index r = 0; r < 50; ++r) {
    const Real* row = q.database().genotype(q.database().size() - 50 + r);
    for (Index j = 0; j < batch.cols(); ++j) ASSERT_EQ(row[j], batch(r, j)) << "row " << r;
  }
}

TEST(QdMetaCmaMae, ACheckpointedRunContinuesBitIdentically) {
  SerialEvaluator evaluator;
  QdMeta straight = small_cma_mae_qd_meta(21, true);
  for (int t = 0; t < 6; ++t) straight.step(evaluator);
  expect_same_run(resumed_run([] { return small_cma_mae_qd_meta(21, true); }, 3, 3, evaluator), straight);
}

TEST(QdMetaCmaMae, EachMapKeepsItsElitesBaseFeatures) {
  SerialEvaluator evaluator;
  QdMeta q = small_cma_mae_qd_meta(4);
  for (int t = 0; t < 3; ++t) q.step(evaluator);
  RastriginParams rp;
  rp.dimensions = 6;
  const Task task{RastriginTask(rp)};
  for (const GridArchive& archive : q.map_archives()) {
    ASSERT_GT(archive.size(), 0);
    for (Index cell : archive.filled_cells()) {
      EvaluationBatch e;
      e.resize(1, task.base_feature_size());
      task.evaluate({archive.solution(cell), 1, archive.solution_size()}, e.view());
      ASSERT_EQ(e.fitness[0], archive.objective(cell));
      for (Index j = 0; j < task.base_feature_size(); ++j) ASSERT_EQ(e.base_features(0, j), archive.base_features(cell)[j]);
    }
  }
}

// Map i's archive rebuilt from `evaluations` uniformly random genotypes of 20-D Rastrigin.
ArchiveStats random_search(const QdMeta& q, Index i, Index evaluations) {
  RastriginParams rp;
  rp.dimensions = 20;
  const Task task{RastriginTask(rp)};
  RowMatrix genotypes(evaluations, task.genotype_size());
  Rng rng(77);
  random_genotypes(genotypes, rng);
  EvaluationBatch e;
  e.resize(evaluations, task.base_feature_size());
  task.evaluate({genotypes.data(), evaluations, task.genotype_size()}, e.view());
  Database db(evaluations, task.genotype_size(), task.base_feature_size());
  db.insert_valid(genotypes, e);
  GridArchive archive = q.map_archives()[static_cast<std::size_t>(i)];
  rebuild_archive(db, *q.feature_map(i), archive);
  return archive.stats();
}

// On 20-D Rastrigin, where random genotypes are poor, every map's elites beat random search's of
// the same budget under the same feature-map: a higher mean and a best higher by a margin that
// an emitter loop no better than random sampling does not reach. (The QD-score is no test here:
// at these 4,000 evaluations random search fills more cells, and each cell's score is mostly the
// offset; it does so against the Gaussian path too.)
TEST(QdMetaCmaMae, FillsEveryMapWithBetterElitesThanRandomSearchOfTheSameBudget) {
  SerialEvaluator evaluator;
  QdMetaParams p = qd_meta_cma_mae_params();
  p.emitters.emitter.x0.assign(20, 0.5);
  QdMeta q = rastrigin_qd_meta_of(p, 8, 20);
  for (int t = 0; t < 8; ++t) q.step(evaluator);
  for (Index i = 0; i < 4; ++i) {
    const ArchiveStats ours = q.map_archives()[static_cast<std::size_t>(i)].stats();
    const ArchiveStats random = random_search(q, i, q.counters().bottom);
    EXPECT_GT(ours.obj_mean, random.obj_mean) << "map " << i;
    EXPECT_GT(ours.obj_max, random.obj_max + 25) << "map " << i;
  }
}

TEST(QdMetaCmaMae, TheEmittersStartAtTheRebuiltArchivesElites) {
  GridArchiveParams grid;
  grid.bins = {4, 4};
  grid.solution_size = 3;
  GridArchive archive(grid);
  const RowMatrix solutions{{0.1f, 0.2f, 0.3f}, {0.9f, 0.8f, 0.7f}};
  const std::vector<Real> objectives{-5.0f, -7.0f};
  const RowMatrix measures{{0.1f, 0.1f}, {0.9f, 0.9f}};
  archive.add_batch({solutions, objectives, measures, {}, {}});
  QdMetaParams p = qd_meta_cma_mae_params();
  p.emitters.emitter.x0.assign(3, 0.5);
  Rng rng(3);
  const auto scheduler = start_map_emitters(archive, p.emitters, rng);
  const CellThresholds& t = scheduler->thresholds();
  std::set<Index> filled(archive.filled_cells().begin(), archive.filled_cells().end());
  for (Index cell = 0; cell < t.cells(); ++cell) {
    const bool elite = filled.contains(cell);
    EXPECT_EQ(t.reached(cell), elite) << cell;
    EXPECT_EQ(t.threshold(cell), elite ? static_cast<double>(archive.objective(cell)) : -2000.0) << cell;
  }
  // Each emitter's first mean is one of the two elites, and both appear among the five.
  std::set<double> firsts;
  for (std::size_t k = 0; k < scheduler->emitter_count(); ++k) {
    const auto& e = static_cast<const EvolutionStrategyEmitter&>(scheduler->emitter(k));
    const double m0 = e.optimiser().state().mean[0];
    EXPECT_TRUE(m0 == static_cast<double>(Real{0.1f}) || m0 == static_cast<double>(Real{0.9f})) << m0;
    firsts.insert(m0);
  }
  EXPECT_EQ(firsts.size(), 2u);
  // An empty archive: x0, and every threshold at threshold_min.
  archive.clear();
  const auto empty = start_map_emitters(archive, p.emitters, rng);
  EXPECT_EQ(static_cast<const EvolutionStrategyEmitter&>(empty->emitter(0)).optimiser().state().mean[0], 0.5);
  EXPECT_FALSE(empty->thresholds().reached(0));
}

TEST(QdMetaCmaMae, ParamsThatDisagreeAreRefused) {
  QdMetaParams p = qd_meta_cma_mae_params();
  p.batch_size = 40;
  EXPECT_INPUT_ERROR(p.validate(), "qd_meta.batch_size = 40 must be emitters.count x emitters.batch_size = 50 with "
                                   "qd_meta.bottom_level = \"cma-mae\" (a generation is one batch of every emitter)");
  p = qd_meta_cma_mae_params();
  p.emitters.emitter.x0.assign(4, 0.5);
  EXPECT_INPUT_ERROR(small_qd_meta_of(p, 1, std::make_unique<StaticControl>(1)),
                     "qd-meta: emitters' x0 has 4 values, the task 6 genes");
}

}  // namespace
}  // namespace qdmeta
