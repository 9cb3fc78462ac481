// Tests of Scheduler and BanditScheduler with AddMode::kBatch (pyribs's add_mode "batch"): the
// thresholds after each tell are those offer_batch gives for the batch against the thresholds
// before it, a run is deterministic and checkpoints continue bit for bit, and it is not the
// single mode (rows of one emitter's batch share cells).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "qdmeta/emitters/bandit_scheduler.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "sphere_problem.hpp"

namespace qdmeta {
namespace {

using test::checkpoint_bytes;
using test::evaluate_sphere;
using test::kSphereGenes;
using test::sphere_grid;
using test::sphere_step;

EvolutionStrategyEmitterParams restarting_emitter_params() {
  EvolutionStrategyEmitterParams p;
  p.x0.assign(kSphereGenes, 0.0);
  p.sigma0 = 0.5;
  p.batch_size = 20;
  p.restart = EmitterRestart::kEveryN;  // restarts draw elites: the continuation reads the archive
  p.restart_every = 10;
  return p;
}

const ThresholdParams kMae{0.05, 0.0};

TEST(SchedulerBatchMode, EachTellIsOfferBatchAgainstTheThresholdsBeforeIt) {
  GridArchive archive(sphere_grid());
  Scheduler s(archive, kMae, make_evolution_strategy_emitters(archive, restarting_emitter_params(), 3), AddMode::kBatch);
  EXPECT_EQ(s.add_mode(), AddMode::kBatch);
  CellThresholds mirror(archive.cells(), kMae);
  Rng rng(3);
  bool shared_cell = false;
  for (int i = 0; i < 15; ++i) {
    std::vector<Real> objectives;
    RowMatrix measures;
    evaluate_sphere(s.ask(rng), objectives, measures);
    std::vector<Index> cells;
    for (Index r = 0; r < measures.rows(); ++r) cells.push_back(archive.index_of(measures.row(r).data()));
    std::vector<ThresholdOutcome> expected(cells.size());
    mirror.offer_batch(cells, objectives, {}, expected);
    s.tell(objectives, measures);
    for (std::size_t r = 0; r < cells.size(); ++r) {
      EXPECT_EQ(s.outcomes()[r].status, expected[r].status);
      EXPECT_EQ(s.outcomes()[r].improvement, expected[r].improvement);
      for (std::size_t q = 0; q < r; ++q) shared_cell |= cells[q] == cells[r];
    }
    EXPECT_EQ(s.thresholds(), mirror);
  }
  EXPECT_TRUE(shared_cell);  // the rule for several rows in one cell was exercised
}

TEST(SchedulerBatchMode, SameSeedSameBitsCheckpointsContinueAndSingleModeDiffers) {
  const auto p = restarting_emitter_params();
  GridArchive a(sphere_grid()), b(sphere_grid()), single(sphere_grid());
  Scheduler sa(a, kMae, make_evolution_strategy_emitters(a, p, 3), AddMode::kBatch);
  Scheduler sb(b, kMae, make_evolution_strategy_emitters(b, p, 3), AddMode::kBatch);
  Scheduler ss(single, kMae, make_evolution_strategy_emitters(single, p, 3));
  Rng ra(21), rb(21), rs(21);
  for (int i = 0; i < 30; ++i) {
    sphere_step(sa, ra);
    sphere_step(sb, rb);
    sphere_step(ss, rs);
  }
  EXPECT_EQ(checkpoint_bytes(a, sa), checkpoint_bytes(b, sb));
  EXPECT_NE(checkpoint_bytes(a, sa), checkpoint_bytes(single, ss));

  const std::string saved = checkpoint_bytes(a, sa);
  GridArchive c(sphere_grid());
  Scheduler sc(c, kMae, make_evolution_strategy_emitters(c, p, 3), AddMode::kBatch);
  BinaryReader in(saved, "test");
  c.load(in);
  sc.load(in);
  in.finish();
  Rng rc = ra;
  for (int i = 0; i < 30; ++i) {
    sphere_step(sa, ra);
    sphere_step(sc, rc);
  }
  EXPECT_EQ(checkpoint_bytes(a, sa), checkpoint_bytes(c, sc));
}

// The BanditScheduler passes its add mode to its Scheduler: with every emitter active it is the
// Scheduler of that mode, row for row.
TEST(SchedulerBatchMode, BanditSchedulerWithAllActiveIsTheBatchScheduler) {
  const auto p = restarting_emitter_params();
  GridArchive a(sphere_grid()), b(sphere_grid());
  BanditScheduler bandit(a, kMae, make_evolution_strategy_emitters(a, p, 3), BanditParams{3, BanditReselect::kAll, 0.05},
                         AddMode::kBatch);
  Scheduler plain(b, kMae, make_evolution_strategy_emitters(b, p, 3), AddMode::kBatch);
  EXPECT_EQ(bandit.scheduler().add_mode(), AddMode::kBatch);
  Rng ra(8), rb(8);
  for (int i = 0; i < 12; ++i) {
    sphere_step(bandit, ra);
    sphere_step(plain, rb);
  }
  EXPECT_EQ(bandit.thresholds(), plain.thresholds());
  BinaryWriter wa, wb;
  a.save(wa);
  b.save(wb);
  EXPECT_EQ(wa.bytes(), wb.bytes());
}

}  // namespace
}  // namespace qdmeta
