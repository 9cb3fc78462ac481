// Tests of src/qdmeta/emitters/emitter_bandit.{hpp,cpp} and bandit_scheduler.hpp: UCB1's choice
// on a hand-computed case, pyribs's choices replayed (pyribs_reference/make_bandit_reference.py
// printed kPyribs* from pyribs 0.12), the settings refused, and a BanditScheduler's determinism
// and checkpoints.
#include "qdmeta/emitters/bandit_scheduler.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "expect_input_error.hpp"
#include "sphere_problem.hpp"

namespace qdmeta {
namespace {

std::vector<int> active_list(const EmitterBandit& b) {
  std::vector<int> out;
  for (std::size_t i = 0; i < b.pool(); ++i)
    if (b.active()[i]) out.push_back(static_cast<int>(i));
  return out;
}

TEST(EmitterBandit, ChoosesByUcb1OnAHandComputedCase) {
  EmitterBandit b(4, BanditParams{2, BanditReselect::kAll, 0.05});
  const std::vector<std::int64_t> no_runs(4, -1);
  b.choose(no_runs);
  EXPECT_EQ(active_list(b), (std::vector<int>{0, 1}));  // the first ask: the pool's first two
  b.record(0, 10, 5);
  b.record(1, 10, 1);
  EXPECT_EQ(b.ucb1(0), 0.5 + 0.05 * std::sqrt(std::log(6.0) / 10));
  EXPECT_EQ(b.ucb1(2), INFINITY);
  b.choose(no_runs);
  EXPECT_EQ(active_list(b), (std::vector<int>{2, 3}));  // never asked: +inf
  b.record(2, 10, 0);
  b.record(3, 10, 3);
  // Successes 5, 1, 0, 3 of 10 rows each; ln 9 / 10 under the root: 0.5234, 0.1234, 0.0234, 0.3234.
  EXPECT_NEAR(b.ucb1(3), 0.3 + 0.05 * std::sqrt(std::log(9.0) / 10), 1e-15);
  b.choose(no_runs);
  EXPECT_EQ(active_list(b), (std::vector<int>{0, 3}));
}

// The script of make_bandit_reference.py: 5 emitters of 10 rows, 12 asks.
int scripted_successes(int step, int i) { return (i + step) % 3 ? std::min(10, (3 * i + 7 * step) % 11) : 0; }
bool scripted_restart(int step, int i) { return (step + i) % 4 == 0; }

std::vector<std::vector<int>> replay(BanditParams p, bool with_runs) {
  EmitterBandit b(5, p);
  std::vector<std::int64_t> runs(5, with_runs ? 0 : -1);
  std::vector<std::vector<int>> out;
  for (int step = 0; step < 12; ++step) {
    b.choose(runs);
    out.push_back(active_list(b));
    for (const int i : out.back()) {
      b.record(static_cast<std::size_t>(i), 10, scripted_successes(step, i));
      if (with_runs && scripted_restart(step, i)) runs[static_cast<std::size_t>(i)] += 1;
    }
  }
  return out;
}

using Sequence = std::vector<std::vector<int>>;

TEST(EmitterBandit, ChoosesAsPyribsGivenTheSameSuccesses) {
  EXPECT_EQ(replay({2, BanditReselect::kAll, 0.05}, false),
            (Sequence{{0, 1}, {3, 4}, {2, 4}, {2, 3}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {2, 4}}));
  EXPECT_EQ(replay({2, BanditReselect::kTerminated, 0.05}, true),
            (Sequence{{0, 1}, {1, 4}, {1, 4}, {1, 4}, {3, 4}, {2, 3}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {2, 4}, {1, 4}}));
  EXPECT_EQ(replay({3, BanditReselect::kTerminated, 1.0}, false),
            (Sequence{{0, 1, 2}, {2, 3, 4}, {1, 3, 4}, {2, 3, 4}, {0, 2, 4}, {0, 1, 4}, {0, 2, 4}, {2, 3, 4},
                      {0, 3, 4}, {2, 3, 4}, {2, 3, 4}, {1, 3, 4}}));
  // The first ask's emitter has no success: its NaN keeps its place, and 4 (of +inf) is taken.
  EXPECT_EQ(replay({1, BanditReselect::kAll, 2.0}, false),
            (Sequence{{0}, {4}, {3}, {2}, {1}, {1}, {4}, {4}, {2}, {4}, {2}, {4}}));
}

TEST(EmitterBandit, RefusesBadSettingsNamingTheKey) {
  EXPECT_INPUT_ERROR(EmitterBandit(3, BanditParams{4, BanditReselect::kAll, 0.05}),
                     "BanditParams.num_active = 4 is out of range: must be in [1, 3] (the pool's size)");
  EXPECT_INPUT_ERROR(EmitterBandit(3, BanditParams{1, BanditReselect::kAll, -1.0}),
                     "BanditParams.zeta = -1 is invalid: must be finite and >= 0");
  EXPECT_INPUT_ERROR(bandit_reselect_from_string("some"), "reselect = 'some' is not 'terminated' or 'all'");
}

EvolutionStrategyEmitterParams es_params() {
  EvolutionStrategyEmitterParams p;
  p.x0.assign(test::kSphereGenes, 0.0);
  p.sigma0 = 0.5;
  p.batch_size = 8;
  p.restart = EmitterRestart::kEveryN;
  p.restart_every = 3;  // runs end often, so reselect "terminated" chooses again
  return p;
}

TEST(BanditScheduler, AsksOnlyTheActiveEmittersAndContinuesCheckpointsBitForBit) {
  const BanditParams bp{2, BanditReselect::kTerminated, 0.05};
  GridArchive a(test::sphere_grid()), b(test::sphere_grid());
  BanditScheduler sa(a, ThresholdParams{0.1, 0.0}, make_evolution_strategy_emitters(a, es_params(), 5), bp);
  BanditScheduler sb(b, ThresholdParams{0.1, 0.0}, make_evolution_strategy_emitters(b, es_params(), 5), bp);
  Rng ra(4), rb(4);
  std::vector<int> times_active(5, 0);
  for (int i = 0; i < 20; ++i) {
    test::sphere_step(sa, ra);
    test::sphere_step(sb, rb);
    EXPECT_EQ(sa.batch_size(), 16);
    for (std::size_t e = 0; e < 5; ++e) times_active[e] += sa.scheduler().active()[e];
  }
  EXPECT_EQ(test::checkpoint_bytes(a, sa), test::checkpoint_bytes(b, sb));
  for (std::size_t e = 0; e < 5; ++e) {
    EXPECT_GT(times_active[e], 0) << e;  // every emitter was tried
    EXPECT_EQ(dynamic_cast<const EvolutionStrategyEmitter&>(sa.scheduler().emitter(e)).tells(), times_active[e]);
    EXPECT_EQ(sa.bandit().selections(e), 8.0 * times_active[e]);
  }

  const std::string saved = test::checkpoint_bytes(a, sa);
  GridArchive c(test::sphere_grid());
  BanditScheduler sc(c, ThresholdParams{0.1, 0.0}, make_evolution_strategy_emitters(c, es_params(), 5), bp);
  BinaryReader in(saved, "test");
  c.load(in);
  sc.load(in);
  in.finish();
  Rng rc = ra;
  for (int i = 0; i < 20; ++i) {
    test::sphere_step(sa, ra);
    test::sphere_step(sc, rc);
  }
  EXPECT_EQ(test::checkpoint_bytes(a, sa), test::checkpoint_bytes(c, sc));
}

}  // namespace
}  // namespace qdmeta
