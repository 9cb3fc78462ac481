// Tests of src/qdmeta/emitters/evolution_strategy_emitter.{hpp,cpp}: the selection rules' parent
// counts, the restart rules firing exactly when they should, the settings refused, determinism
// and bit-exact continuation from a checkpoint.
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "expect_input_error.hpp"

namespace qdmeta {
namespace {

constexpr int kBatch = 6;

EvolutionStrategyEmitterParams es_emitter_params(EmitterRestart restart = EmitterRestart::kNoImprovement,
                                                 int every = 0) {
  EvolutionStrategyEmitterParams p;
  p.x0 = {0.5, 0.5, 0.5};
  p.sigma0 = 0.2;
  p.batch_size = kBatch;
  p.restart = restart;
  p.restart_every = every;
  return p;
}

// A restart's mean: always (0.25, 0.25, 0.25).
bool quarter(Rng&, std::vector<double>& mean) {
  std::fill(mean.begin(), mean.end(), 0.25);
  return true;
}

// Tells the emitter its pending batch with `added` rows new (the first ones) and the rest not
// added; objectives and improvement values are distinct, from the genes.
void tell_with(EvolutionStrategyEmitter& e, const RowMatrix& batch, int added) {
  std::vector<Real> objectives(kBatch);
  std::vector<ThresholdOutcome> outcomes(kBatch);
  const RowMatrix measures = batch.leftCols(2);  // for the random-direction rankers
  for (int r = 0; r < kBatch; ++r) {
    objectives[static_cast<std::size_t>(r)] = batch(r, 0) + 2.0f * batch(r, 1);
    outcomes[static_cast<std::size_t>(r)] = {r < added ? AddStatus::kNew : AddStatus::kNotAdded,
                                             static_cast<double>(objectives[static_cast<std::size_t>(r)])};
  }
  e.tell({batch, objectives, measures, outcomes});
}

TEST(EvolutionStrategyEmitter, FilterTakesTheAddedRowsAsParentsAndMuHalf) {
  EvolutionStrategyEmitter filter(es_emitter_params(), quarter);
  Rng rng(3);
  tell_with(filter, filter.ask(rng), 4);
  EXPECT_EQ(filter.last_parents(), 4);
  auto p = es_emitter_params();
  p.selection = EmitterSelection::kMu;
  EvolutionStrategyEmitter mu(p, quarter);
  tell_with(mu, mu.ask(rng), 1);
  EXPECT_EQ(mu.last_parents(), kBatch / 2);
}

TEST(EvolutionStrategyEmitter, NoImprovementRestartsExactlyAfterABatchWithNothingAdded) {
  EvolutionStrategyEmitter e(es_emitter_params(), quarter);
  Rng rng(4);
  for (int t = 0; t < 5; ++t) {
    tell_with(e, e.ask(rng), 1 + t % 3);
    EXPECT_FALSE(e.restart_pending()) << t;
  }
  const CmaEsState before = e.optimiser().state();
  tell_with(e, e.ask(rng), 0);  // filter: no parents, so CMA-ES keeps its distribution
  EXPECT_TRUE(e.restart_pending());
  EXPECT_TRUE(e.optimiser().state().mean == before.mean);
  EXPECT_EQ(e.restarts(), 0);
  e.ask(rng);  // the restart happens here, from the picked elite
  EXPECT_EQ(e.restarts(), 1);
  EXPECT_FALSE(e.restart_pending());
  EXPECT_EQ(e.optimiser().state().mean, Eigen::VectorXd::Constant(3, 0.25));
  EXPECT_EQ(e.optimiser().state().sigma, 0.2);
  EXPECT_EQ(e.optimiser().state().generation, 0);
}

TEST(EvolutionStrategyEmitter, BasicIgnoresEmptyBatchesButRestartsOnAFlatRanking) {
  EvolutionStrategyEmitter e(es_emitter_params(EmitterRestart::kBasic), quarter);
  Rng rng(5);
  for (int t = 0; t < 6; ++t) {
    tell_with(e, e.ask(rng), 0);
    EXPECT_FALSE(e.restart_pending()) << t;
  }
  // Every row with the same status and value: the ranking is flat, which is convergence.
  const RowMatrix& batch = e.ask(rng);
  const std::vector<Real> objectives(kBatch, 1.0f);
  const std::vector<ThresholdOutcome> outcomes(kBatch, {AddStatus::kImproved, 0.5});
  e.tell({batch, objectives, {}, outcomes});
  EXPECT_TRUE(e.restart_pending());
}

TEST(EvolutionStrategyEmitter, EveryNRestartsOnEveryNthTell) {
  EvolutionStrategyEmitter e(es_emitter_params(EmitterRestart::kEveryN, 3), quarter);
  Rng rng(6);
  std::vector<int> fired;
  for (int t = 1; t <= 9; ++t) {
    tell_with(e, e.ask(rng), 2);
    if (e.restart_pending()) fired.push_back(t);
  }
  EXPECT_EQ(fired, (std::vector<int>{3, 6, 9}));
  EXPECT_EQ(e.restarts(), 2);  // the third restart waits for the next ask
}

TEST(EvolutionStrategyEmitter, ConvergedOnConditionNumberAndWidth) {
  CmaEsParams two;
  two.dimension = 2;
  CmaEsState s = CmaEs::initial_state(two);
  const std::vector<RankKey> spread = {{1, 2.0}, {0, 1.0}};
  EXPECT_FALSE(cma_converged(s, spread));
  s.D << 1.0, 1e-7;  // condition number 1e14: not above it
  EXPECT_FALSE(cma_converged(s, spread));
  s.D << 1.0, 0.99e-7;
  EXPECT_TRUE(cma_converged(s, spread));
  s.D << 1.0, 1.0;
  s.sigma = 0.99e-11;
  EXPECT_TRUE(cma_converged(s, spread));
  s.sigma = 1.0;
  EXPECT_TRUE(cma_converged(s, {{1, 2.0}, {1, 2.0}}));
  EXPECT_FALSE(cma_converged(s, {{1, 2.0}}));
}

TEST(EvolutionStrategyEmitter, RefusesBadSettingsNamingTheKey) {
  auto p = es_emitter_params();
  p.batch_size = 0;
  EXPECT_INPUT_ERROR(p.validate(), "emitters.batch_size = 0 is out of range: must be in [1, 1000000]");
  p = es_emitter_params();
  p.sigma0 = 0.0;
  EXPECT_INPUT_ERROR(p.validate(), "emitters.sigma0 = 0 is out of range: must be a positive number");
  p.sigma0 = -1.0;
  EXPECT_INPUT_ERROR(EvolutionStrategyEmitter(p, quarter),
                     "emitters.sigma0 = -1 is out of range: must be a positive number");
  p = es_emitter_params();
  p.x0.clear();
  EXPECT_INPUT_ERROR(p.validate(), "EvolutionStrategyEmitterParams.x0 is empty: give the first mean, one value per gene");
  EXPECT_INPUT_ERROR(es_emitter_params(EmitterRestart::kEveryN, 0).validate(),
                     "emitters.restart_every = 0 is out of range: must be in [1, 1000000000]");
  EvolutionStrategyEmitter e(es_emitter_params(), quarter);
  EXPECT_INPUT_ERROR(tell_with(e, RowMatrix::Zero(kBatch, 3), 1),
                     "EvolutionStrategyEmitter::tell: called without a pending ask; call ask() first");
  Rng rng(1);
  e.ask(rng);
  EXPECT_INPUT_ERROR(e.ask(rng),
                     "EvolutionStrategyEmitter::ask: called twice without tell; tell the last batch's outcomes first");
}

TEST(EvolutionStrategyEmitter, RandomDirectionIsDrawnAtTheFirstAskAndAtEachRestart) {
  auto p = es_emitter_params(EmitterRestart::kEveryN, 2);
  p.ranker = EmitterRanker::kTwoStageRandomDirection;
  p.measure_ranges = {2.0, 0.5};
  EvolutionStrategyEmitter e(p, quarter);
  EXPECT_TRUE(e.direction().empty());
  Rng rng(12);
  Rng draws = rng;  // the direction takes the stream's first two normals
  const double z0 = draws.normal(), z1 = draws.normal();
  const RowMatrix batch = e.ask(rng);
  EXPECT_EQ(e.direction(), (std::vector<double>{z0 * 2.0, z1 * 0.5}));
  RowMatrix measures = RowMatrix::Zero(kBatch, 2);
  const std::vector<Real> objectives(kBatch, 0.0f);
  const std::vector<ThresholdOutcome> outcomes(kBatch, {AddStatus::kNew, 0.0});
  const RowMatrix three = RowMatrix::Zero(kBatch, 3);
  EXPECT_INPUT_ERROR(e.tell({batch, objectives, three, outcomes}),
                     "rank_keys: the two-stage-random-direction ranker has a direction of 2 values for 3 measures");
  for (Index r = 0; r < kBatch; ++r) measures(r, 0) = static_cast<Real>(r);
  e.tell({batch, objectives, measures, outcomes});
  const std::vector<double> first = e.direction();
  tell_with(e, e.ask(rng), 1);  // the second tell: every-2 fires
  EXPECT_TRUE(e.restart_pending());
  e.ask(rng);
  EXPECT_EQ(e.restarts(), 1);
  EXPECT_NE(e.direction(), first);

  p.measure_ranges.clear();
  EXPECT_INPUT_ERROR(p.validate(), "EvolutionStrategyEmitterParams.measure_ranges is empty: the "
                                   "two-stage-random-direction ranker needs the extent of each measure");
  p.measure_ranges = {1.0, 0.0};
  EXPECT_INPUT_ERROR(p.validate(), "EvolutionStrategyEmitterParams.measure_ranges[1] = 0 is invalid: must be finite and > 0");
}

// Runs `tells` ask/tell rounds with outcomes that vary (including empty batches, so restarts happen).
void run_es_emitter(EvolutionStrategyEmitter& e, Rng& rng, int first, int tells) {
  for (int t = first; t < first + tells; ++t) tell_with(e, e.ask(rng), (t * 5) % 7 % 4);
}

// Two emitters of `p` and seed 9 reach the same state (`state` reads it); one saved after 20
// tells and loaded into a third continues to the first's bits. Returns the third.
template <class ReadState>
EvolutionStrategyEmitter expect_same_bits_and_continuation(const EvolutionStrategyEmitterParams& p, ReadState state) {
  EvolutionStrategyEmitter a(p, quarter), b(p, quarter);
  Rng ra(9), rb(9);
  run_es_emitter(a, ra, 0, 20);
  run_es_emitter(b, rb, 0, 20);
  EXPECT_TRUE(state(a) == state(b));
  EXPECT_GT(a.restarts(), 0);

  BinaryWriter out;
  a.save(out);
  EvolutionStrategyEmitter resumed(p, quarter);
  BinaryReader in(out.bytes(), "test");
  resumed.load(in);
  in.finish();
  Rng rr = ra;
  run_es_emitter(a, ra, 20, 15);
  run_es_emitter(resumed, rr, 20, 15);
  EXPECT_TRUE(state(a) == state(resumed));
  EXPECT_EQ(a.restarts(), resumed.restarts());
  EXPECT_EQ(a.tells(), resumed.tells());
  return resumed;
}

TEST(EvolutionStrategyEmitter, SameSeedSameBitsAndCheckpointsContinueBitForBit) {
  expect_same_bits_and_continuation(es_emitter_params(),
                                    [](const EvolutionStrategyEmitter& e) { return e.optimiser().state(); });
}

// es = sep-cma-es: the emitter runs meta/sep_cma_es.hpp's separable CMA-ES through the same
// rules: same bits for the same seed, restarts to the picked mean, checkpoints that continue.
TEST(EvolutionStrategyEmitter, SeparableEsSameBitsRestartsAndCheckpointsContinueBitForBit) {
  auto p = es_emitter_params();
  p.es = EvolutionStrategyKind::kSepCmaEs;
  EvolutionStrategyEmitter resumed = expect_same_bits_and_continuation(
      p, [](const EvolutionStrategyEmitter& e) { return e.separable_optimiser().state(); });
  EXPECT_GT(resumed.separable_optimiser().state().generation, 0);
  // A full ES's checkpoint does not load into a separable emitter.
  BinaryWriter full;
  EvolutionStrategyEmitter(es_emitter_params(), quarter).save(full);
  BinaryReader wrong(full.bytes(), "test");
  EXPECT_THROW(resumed.load(wrong), InputError);

  // A batch of nothing added restarts the separable ES at the picked mean.
  EvolutionStrategyEmitter e(p, quarter);
  Rng rng(2);
  tell_with(e, e.ask(rng), 0);
  e.ask(rng);
  EXPECT_EQ(e.separable_optimiser().state().mean, Eigen::VectorXd::Constant(3, 0.25));
  EXPECT_EQ(e.separable_optimiser().state().generation, 0);
}

TEST(EvolutionStrategyEmitter, SeparableEsRefusesTheFullEsOnlySettingsAndTheOtherAccessor) {
  auto p = es_emitter_params();
  p.es = EvolutionStrategyKind::kSepCmaEs;
  p.rank_one = CmaRankOne::kPyribs;
  EXPECT_INPUT_ERROR(p.validate(), "EvolutionStrategyEmitterParams.rank_one = pyribs is not available with es = "
                                   "sep-cma-es: only tutorial");
  p.rank_one = CmaRankOne::kTutorial;
  const EvolutionStrategyEmitter sep(p, quarter);
  EXPECT_INPUT_ERROR(sep.optimiser(),
                     "EvolutionStrategyEmitter::optimiser: this emitter runs es = sep-cma-es; use separable_optimiser()");
  const EvolutionStrategyEmitter full(es_emitter_params(), quarter);
  EXPECT_INPUT_ERROR(full.separable_optimiser(),
                     "EvolutionStrategyEmitter::separable_optimiser: this emitter runs es = cma-es; use optimiser()");
  EXPECT_EQ(evolution_strategy_kind_from_string("sep-cma-es"), EvolutionStrategyKind::kSepCmaEs);
  EXPECT_EQ(to_string(EvolutionStrategyKind::kCmaEs), "cma-es");
  EXPECT_THROW(evolution_strategy_kind_from_string("sep_cma"), InputError);
}

}  // namespace
}  // namespace qdmeta
