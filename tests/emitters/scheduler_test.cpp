// Tests of src/qdmeta/emitters/scheduler.hpp: the ask/tell loop's bookkeeping, the settings
// refused, determinism and checkpoints, and CMA-ME and CMA-MAE against Gaussian MAP-Elites on a
// 10-D sphere with a linear-projection measure at equal evaluations (sphere_problem.hpp).
#include "qdmeta/emitters/scheduler.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/core/fused.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "sphere_problem.hpp"
#include "threshold_cases.hpp"

namespace qdmeta {
namespace {

using test::checkpoint_bytes;
using test::evaluate_sphere;
using test::kSphereGenes;
using test::sphere_grid;
using test::mae;
using test::sphere_step;

constexpr int kEmitters = 5;
constexpr int kEmitterBatch = 20;
constexpr int kIterations = 200;  // 5 x 20 x 200 = 20,000 evaluations per run
constexpr double kMinusInf = -std::numeric_limits<double>::infinity();

EvolutionStrategyEmitterParams emitter_params() {
  EvolutionStrategyEmitterParams p;
  p.x0.assign(kSphereGenes, 0.0);
  p.sigma0 = 0.5;
  p.batch_size = kEmitterBatch;
  return p;
}

double emitter_qd_score(ThresholdParams t, EmitterRanker ranker, std::uint64_t seed) {
  GridArchive archive(sphere_grid());
  auto p = emitter_params();
  p.ranker = ranker;
  Scheduler scheduler(archive, t, make_evolution_strategy_emitters(archive, p, kEmitters));
  Rng rng(seed);
  for (int i = 0; i < kIterations; ++i) sphere_step(scheduler, rng);
  return archive.stats().qd_score;
}

// Gaussian MAP-Elites with the same evaluations, written out: one batch drawn from CMA-ES's first
// distribution (N(0, 0.5^2) in every gene), then batches of uniformly drawn elites with
// N(0, 0.5^2) added to every gene (the MAP-Elites baseline of the CMA-ME paper).
void run_map_elites(GridArchive& archive, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix x(kEmitters * kEmitterBatch, kSphereGenes);
  std::vector<Real> objectives;
  RowMatrix measures;
  for (int i = 0; i < kIterations; ++i) {
    for (Index r = 0; r < x.rows(); ++r) {
      const Real* parent = i == 0 ? nullptr : archive.solution(archive.sample_cell(rng));
      for (Index j = 0; j < kSphereGenes; ++j) {
        x(r, j) = static_cast<Real>(fused(0.5, rng.normal(), parent ? parent[j] : 0.0));
      }
    }
    evaluate_sphere(x, objectives, measures);
    archive.add_batch(EliteBatch{x, objectives, measures, {}, {}});
  }
}

double map_elites_qd_score(std::uint64_t seed) {
  GridArchive archive(sphere_grid());
  run_map_elites(archive, seed);
  return archive.stats().qd_score;
}

TEST(Scheduler, SolutionsAreZeroBeforeTheFirstAskThenTheLastBatch) {
  GridArchive archive(sphere_grid());
  Scheduler scheduler(archive, mae(1.0, kMinusInf), make_evolution_strategy_emitters(archive, emitter_params(), 2));
  EXPECT_TRUE(scheduler.solutions().isZero(0));
  EXPECT_EQ(scheduler.solutions().rows(), 2 * kEmitterBatch);
  Rng rng(3);
  const RowMatrix first = scheduler.ask(rng);
  EXPECT_EQ(scheduler.solutions(), first);
  EXPECT_FALSE(first.isZero(0));
}

TEST(Scheduler, GaussianEmittersAtAlphaOneAreMapElitesBitForBit) {
  GridArchive written_out(sphere_grid()), scheduled(sphere_grid());
  run_map_elites(written_out, 4);
  GaussianEmitterParams p;
  p.x0.assign(kSphereGenes, 0.0);
  p.sigma = 0.5;
  p.batch_size = kEmitters * kEmitterBatch;
  std::vector<std::unique_ptr<Emitter>> emitters;
  emitters.push_back(std::make_unique<GaussianEmitter>(p, elite_picker(scheduled)));
  Scheduler scheduler(scheduled, mae(1.0, kMinusInf), std::move(emitters));
  Rng rng(4);
  for (int i = 0; i < kIterations; ++i) sphere_step(scheduler, rng);
  BinaryWriter a, b;
  written_out.save(a);
  scheduled.save(b);
  EXPECT_EQ(a.bytes(), b.bytes());
  EXPECT_GT(scheduled.size(), 100);
}

TEST(Scheduler, CmaMeAndCmaMaeBeatGaussianMapElitesAtEqualEvaluations) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const double me = map_elites_qd_score(seed);
    const double cma_me = emitter_qd_score(mae(1.0, kMinusInf), EmitterRanker::kTwoStageImprovement, seed);
    const double cma_mae = emitter_qd_score(mae(0.01, 0.0), EmitterRanker::kImprovement, seed);
    std::printf("seed %d: MAP-Elites %.1f, CMA-ME %.1f, CMA-MAE %.1f\n", static_cast<int>(seed), me, cma_me, cma_mae);
    EXPECT_GT(cma_me, me) << "seed " << seed;
    EXPECT_GT(cma_mae, me) << "seed " << seed;
  }
}

TEST(Scheduler, StacksTheEmittersBatchesAndTellsEachItsOwnRows) {
  GridArchive archive(sphere_grid());
  Scheduler scheduler(archive, mae(1.0, kMinusInf), make_evolution_strategy_emitters(archive, emitter_params(), 3));
  EXPECT_EQ(scheduler.batch_size(), 3 * kEmitterBatch);
  Rng rng(8);
  std::vector<Real> objectives;
  RowMatrix measures;
  for (int i = 0; i < 4; ++i) {
    const RowMatrix x = scheduler.ask(rng);
    evaluate_sphere(x, objectives, measures);
    scheduler.tell(objectives, measures);
    // Each row's outcome is the thresholds' verdict, and at alpha = 1 the archive holds it.
    for (Index r = 0; r < x.rows(); ++r) {
      const Index cell = archive.index_of(measures.row(r).data());
      if (scheduler.outcomes()[static_cast<std::size_t>(r)].status != AddStatus::kNotAdded) {
        EXPECT_GE(archive.objective(cell), objectives[static_cast<std::size_t>(r)]);
      }
      EXPECT_EQ(scheduler.thresholds().threshold(cell), static_cast<double>(archive.objective(cell)));
    }
  }
  for (std::size_t e = 0; e < scheduler.emitter_count(); ++e) {
    EXPECT_EQ(dynamic_cast<const EvolutionStrategyEmitter&>(scheduler.emitter(e)).tells(), 4);
  }
}

TEST(Scheduler, RefusesBadSettingsNamingTheKey) {
  GridArchive archive(sphere_grid());
  EXPECT_INPUT_ERROR(Scheduler(archive, mae(1.0, kMinusInf), {}),
                     "Scheduler emitters is empty: give at least one emitter");
  EXPECT_INPUT_ERROR(Scheduler(archive, mae(1.5, 0.0), make_evolution_strategy_emitters(archive, emitter_params(), 1)),
                     "archive.learning_rate = 1.5 is out of range: must be in [0, 1]");
  auto p = emitter_params();
  p.x0.assign(3, 0.0);
  EXPECT_INPUT_ERROR(Scheduler(archive, mae(1.0, kMinusInf), make_evolution_strategy_emitters(archive, p, 2)),
                     "Scheduler emitters[0] proposes 3 genes; the archive holds 10");
  Scheduler scheduler(archive, mae(1.0, kMinusInf), make_evolution_strategy_emitters(archive, emitter_params(), 1));
  EXPECT_INPUT_ERROR(scheduler.tell({}, RowsView()), "Scheduler::tell: called without a pending ask; call ask() first");
  // A tell of the wrong size changes nothing: the same batch can then be told in full.
  Rng rng(2);
  std::vector<Real> objectives;
  RowMatrix measures;
  evaluate_sphere(scheduler.ask(rng), objectives, measures);
  const std::vector<Real> short_objectives(objectives.begin(), objectives.begin() + 3);
  EXPECT_INPUT_ERROR(scheduler.tell(short_objectives, measures), "grid archive: the batch has 3 objectives for 20 rows");
  EXPECT_TRUE(archive.empty());
  scheduler.tell(objectives, measures);
  EXPECT_FALSE(archive.empty());
}

TEST(Scheduler, SameSeedSameBitsAndCheckpointsContinueBitForBit) {
  const auto tp = mae(0.05, 0.0);
  auto p = emitter_params();  // restarts every 10 tells, so that the continuation draws elites
  p.restart = EmitterRestart::kEveryN;
  p.restart_every = 10;
  GridArchive a(sphere_grid()), b(sphere_grid());
  Scheduler sa(a, tp, make_evolution_strategy_emitters(a, p, 3));
  Scheduler sb(b, tp, make_evolution_strategy_emitters(b, p, 3));
  Rng ra(21), rb(21);
  for (int i = 0; i < 30; ++i) {
    sphere_step(sa, ra);
    sphere_step(sb, rb);
  }
  EXPECT_EQ(checkpoint_bytes(a, sa), checkpoint_bytes(b, sb));

  const std::string saved = checkpoint_bytes(a, sa);
  GridArchive c(sphere_grid());
  Scheduler sc(c, tp, make_evolution_strategy_emitters(c, p, 3));
  BinaryReader in(saved, "test");
  c.load(in);
  sc.load(in);
  in.finish();
  Rng rc = ra;
  std::int64_t restarts = 0;
  for (int i = 0; i < 40; ++i) {
    sphere_step(sa, ra);
    sphere_step(sc, rc);
  }
  for (std::size_t e = 0; e < sa.emitter_count(); ++e) {
    restarts += dynamic_cast<const EvolutionStrategyEmitter&>(sa.emitter(e)).restarts();
  }
  EXPECT_EQ(checkpoint_bytes(a, sa), checkpoint_bytes(c, sc));
  EXPECT_GT(restarts, 0);  // the continuation went through restarts, which draw elites
}

}  // namespace
}  // namespace qdmeta
