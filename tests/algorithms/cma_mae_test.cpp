// qdmeta::CmaMae, the algorithm of "cma-me" / "cma-mae": exactly the emitter scheduler's loop
// (one ask/tell per step on the stream (seed, kVariation, generation), measures from the
// feature-map), invalid rows enter no cell, a checkpoint between steps continues to the same
// bits, and mismatched parts are refused in one line.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/iso_line_emitter.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "small_cma_mae.hpp"

namespace qdmeta {
namespace {

constexpr int kGenes = 8;

Task cma_mae_rastrigin() {
  RastriginParams rp;
  rp.dimensions = kGenes;
  return Task(RastriginTask(rp));
}

CmaMaeParams params() { return test::small_cma_mae(kGenes, 0.3, 3, 12, CmaBoundsHandling::kClamp, {0.05, -50.0}); }

GridArchiveParams grid() {
  GridArchiveParams g;
  g.bins = {12, 12};
  g.solution_size = kGenes;
  return g;
}

// Measures are genes 2 and 5, so a mix-up of base features and measures shows.
std::unique_ptr<FeatureMap> genes_2_and_5() { return std::make_unique<SelectFeatureMap>(kGenes, std::vector<int>{2, 5}); }

std::unique_ptr<CmaMae<GridArchive>> make(Task task = cma_mae_rastrigin(), CmaMaeParams p = params()) {
  return std::make_unique<CmaMae<GridArchive>>(p, std::move(task), genes_2_and_5(),
                                               [](Evaluator*) { return GridArchive(grid()); }, 21);
}

TEST(CmaMae, IsTheSchedulersLoopOnTheStepsStreams) {
  auto algorithm = make();
  SerialEvaluator serial;
  for (int s = 0; s < 40; ++s) algorithm->step(serial);

  const Task task = cma_mae_rastrigin();
  GridArchive archive(grid());
  const CmaMaeParams p = params();
  Scheduler scheduler(archive, p.thresholds, make_evolution_strategy_emitters(archive, p.emitter, p.emitters));
  EvaluationBatch results;
  RowMatrix measures;
  for (std::uint64_t g = 0; g < 40; ++g) {
    Rng rng = Rng::stream(21, {key(StreamKey::kVariation), g});
    const RowMatrix& x = scheduler.ask(rng);
    results.resize(x.rows(), kGenes);
    task.evaluate({x.data(), x.rows(), x.cols()}, results.view());
    measures.resize(x.rows(), 2);
    measures.col(0) = results.base_features.col(2);
    measures.col(1) = results.base_features.col(5);
    scheduler.tell({results.fitness.data(), static_cast<std::size_t>(x.rows())}, measures);
  }
  EXPECT_EQ(algorithm->counters().bottom, 40 * 36);
  EXPECT_EQ(algorithm->stats(), archive.stats());
  EXPECT_GT(archive.size(), 40);
  EXPECT_TRUE(algorithm->elites().solutions == archive.elites().solutions);
  EXPECT_EQ(algorithm->scheduler().thresholds(), scheduler.thresholds());
}

// Rastrigin whose rows with gene 0 above 0.4 are invalid, their results NaN.
struct HalfInvalid {
  RastriginTask inner;
  Index genotype_size() const { return inner.genotype_size(); }
  Index base_feature_size() const { return inner.base_feature_size(); }
  void evaluate(GenotypeView g, EvaluationView out) const {
    inner.evaluate(g, out);
    for (Index r = 0; r < out.count; ++r) {
      if (g.row(r)[0] <= 0.4f) continue;
      out.valid[r] = 0;
      out.fitness[r] = std::numeric_limits<Real>::quiet_NaN();
      for (Index j = 0; j < out.base_feature_size; ++j) out.base_row(r)[j] = std::numeric_limits<Real>::quiet_NaN();
    }
  }
};

TEST(CmaMae, InvalidRowsEnterNoCellAndLeaveTheRankingsFinite) {
  RastriginParams rp;
  rp.dimensions = kGenes;
  CmaMaeParams p = params();
  p.emitter.x0.assign(kGenes, 0.45);  // about half of the first batches invalid
  p.emitter.ranker = EmitterRanker::kTwoStageRandomDirection;
  p.emitter.measure_ranges = {1.0, 1.0};
  auto algorithm = make(Task(HalfInvalid{RastriginTask(rp)}), p);
  SerialEvaluator serial;
  for (int s = 0; s < 30; ++s) algorithm->step(serial);
  const EliteTable t = algorithm->elites();
  ASSERT_GT(t.size(), 10);
  for (Index i = 0; i < t.size(); ++i) {
    ASSERT_LE(t.solutions(i, 0), 0.4f) << "an invalid row entered, row " << i;
    ASSERT_TRUE(std::isfinite(t.objective[static_cast<std::size_t>(i)]));
  }
  for (Index c = 0; c < algorithm->scheduler().thresholds().cells(); ++c)
    ASSERT_TRUE(std::isfinite(algorithm->scheduler().thresholds().threshold(c)));
}

TEST(CmaMae, ACheckpointBetweenStepsContinuesToTheSameBits) {
  auto straight = make();
  auto first = make();
  SerialEvaluator serial;
  for (int s = 0; s < 50; ++s) straight->step(serial);
  for (int s = 0; s < 20; ++s) first->step(serial);
  BinaryWriter out;
  first->save(out);
  auto second = make();
  BinaryReader in(out.bytes(), "memory");
  second->load(in);
  in.finish();
  for (int s = 20; s < 50; ++s) second->step(serial);
  EXPECT_EQ(second->generation(), 50);
  EXPECT_EQ(second->stats(), straight->stats());
  EXPECT_TRUE(second->elites().solutions == straight->elites().solutions);
  EXPECT_EQ(second->scheduler().thresholds(), straight->scheduler().thresholds());
  EXPECT_EQ(second->summary_extras(), straight->summary_extras());
}

// kind gaussian / iso-line: the scheduler holds those emitters with the shared x0, batch_size and
// gene bounds and their own sigmas; they never restart; bad sigmas are refused naming the field.
TEST(CmaMae, GaussianAndIsoLineKindsMakeThoseEmittersWithTheSharedSettings) {
  SerialEvaluator serial;
  CmaMaeParams p = params();
  p.kind = EmitterKind::kGaussian;
  p.sigma = 0.07;
  auto gaussian = make(cma_mae_rastrigin(), p);
  for (int s = 0; s < 5; ++s) gaussian->step(serial);
  ASSERT_EQ(gaussian->scheduler().emitter_count(), 3u);
  const auto& g = dynamic_cast<const GaussianEmitter&>(gaussian->scheduler().emitter(2));
  EXPECT_EQ(g.params().sigma, 0.07);
  EXPECT_EQ(g.params().batch_size, 12);
  EXPECT_EQ(g.params().x0, std::vector<double>(kGenes, 0.3));
  EXPECT_EQ(g.params().lower_bound, 0.0);
  EXPECT_EQ(g.params().upper_bound, 1.0);
  EXPECT_GT(gaussian->stats().num_elites, 0);
  EXPECT_EQ(gaussian->summary_extras(), (std::vector<std::pair<std::string, double>>{{"emitter_restarts", 0.0}}));

  p = params();
  p.kind = EmitterKind::kIsoLine;
  p.iso_sigma = 0.0;
  p.line_sigma = 0.4;
  auto iso = make(cma_mae_rastrigin(), p);
  iso->step(serial);
  const auto& l = dynamic_cast<const IsoLineEmitter&>(iso->scheduler().emitter(0));
  EXPECT_EQ(l.params().iso_sigma, 0.0);
  EXPECT_EQ(l.params().line_sigma, 0.4);
  EXPECT_EQ(l.params().upper_bound, 1.0);

  p.kind = EmitterKind::kGaussian;
  p.sigma = 0.0;
  EXPECT_INPUT_ERROR(make(cma_mae_rastrigin(), p), "emitters.sigma = 0 is out of range: must be a positive number");
  p.kind = EmitterKind::kIsoLine;
  p.iso_sigma = -1.0;
  EXPECT_INPUT_ERROR(make(cma_mae_rastrigin(), p), "emitters.iso_sigma = -1 is out of range: must be a number >= 0");
  p.kind = static_cast<EmitterKind>(7);
  EXPECT_INPUT_ERROR(make(cma_mae_rastrigin(), p),
                     "CmaMaeParams.kind = 7 is invalid: must be one of evolution-strategy, gaussian, iso-line");
}

TEST(CmaMae, RefusesPartsThatDoNotFit) {
  CmaMaeParams p = params();
  p.emitter.x0.assign(3, 0.5);
  EXPECT_INPUT_ERROR(make(cma_mae_rastrigin(), p), "cma-mae: x0 has 3 values, the task 8 genes");
  p = params();
  p.emitters = 0;
  EXPECT_NE(input_error_message([&] { make(cma_mae_rastrigin(), p); }).find("emitters.count = 0"), std::string::npos);
  p = params();
  p.thresholds.alpha = 1.5;
  EXPECT_NE(input_error_message([&] { make(cma_mae_rastrigin(), p); }).find("archive.learning_rate = 1.5"), std::string::npos);
  auto wrong_archive = std::make_unique<CmaMae<GridArchive>>(
      params(), cma_mae_rastrigin(), genes_2_and_5(),
      [](Evaluator*) {
        GridArchiveParams g = grid();
        g.bins = {4, 4, 4};
        return GridArchive(g);
      },
      1);
  SerialEvaluator serial;
  EXPECT_INPUT_ERROR(wrong_archive->step(serial),
                     "cma-mae: the archive holds 8 genes over 3 measures; the task has 8 genes and the feature-map "
                     "makes 2 measures (and it must start empty)");
}

}  // namespace
}  // namespace qdmeta
