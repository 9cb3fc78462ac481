// RHex episode cost (bench/README.md): one 5 s episode of a tripod gait per collision detector
// and leg model on one core, and random controllers through the ThreadEvaluator.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/rhex_mujoco_variants.hpp"

namespace qdmeta {
namespace {


// Times the hand-set tripod gait's 5 s episode on flat ground under `params`; the last result.
rhex::EpisodeResult time_tripod_episode(benchmark::State& state, const RhexParams& params) {
  const RhexTask task(params);
  const auto genes = rhex::tripod_genes();
  rhex::EpisodeResult result;
  for (auto _ : state) {
    result = task.episode(genes.data(), {});
    benchmark::DoNotOptimize(result.fitness);
  }
  state.counters["fitness_m"] = result.fitness;
  state.counters["contacts_per_step"] = static_cast<double>(result.contacts) / std::max(1, result.walk_steps);
  return result;
}

void BM_RhexEpisode(benchmark::State& state) {
  RhexParams params;
  params.episode.collision = static_cast<rhex::CollisionKind>(state.range(0));
  params.episode.legs = static_cast<rhex::LegModel>(state.range(1));
  const rhex::EpisodeResult result = time_tripod_episode(state, params);
  state.SetLabel(std::string(enum_to_string(rhex::kCollisionKindNames, params.episode.collision)) + "/" +
                 std::string(enum_to_string(rhex::kLegModelNames, params.episode.legs)));
  state.counters["dead"] = result.dead;
  state.counters["steps"] = result.walk_steps + result.settle_steps;
}
BENCHMARK(BM_RhexEpisode)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->ArgNames({"collision", "legs"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// DART and MuJoCo side by side (docs/fidelity.md, "RHex on MuJoCo"): the tripod's 5 s episode
// with rigid and with compliant legs on each engine (bench/README.md). MuJoCo only where built
// with it.
// False (the benchmark skipped, saying why) where `params` are refused or name an engine this
// build lacks: one short episode says.
bool runs(benchmark::State& state, const RhexParams& params) {
  try {
    RhexParams probe = params;
    probe.episode.duration = 10 * probe.episode.time_step;
    const auto genes = rhex::tripod_genes();
    RhexTask(probe).episode(genes.data(), {});
  } catch (const InputError& e) {
    state.SkipWithError(e.what());
    return false;
  }
  return true;
}

void BM_RhexEngine(benchmark::State& state) {
  RhexParams params;
  params.episode.engine = static_cast<rhex::Engine>(state.range(0));
  params.episode.legs = static_cast<rhex::LegModel>(state.range(1));
  if (!runs(state, params)) return;
  const rhex::EpisodeResult result = time_tripod_episode(state, params);
  state.SetLabel(std::string(enum_to_string(rhex::kEngineNames, params.episode.engine)) + "/" +
                 std::string(enum_to_string(rhex::kLegModelNames, params.episode.legs)));
  state.counters["steps"] = result.walk_steps + result.settle_steps;
}
BENCHMARK(BM_RhexEngine)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"engine", "legs"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// MuJoCo's option variants (bench/tasks/rhex_mujoco_variants.hpp; their agreement with the
// faithful setting and with DART: rhex_mujoco_settings): the tripod's episode per variant and leg
// model (bench/README.md, "MuJoCo's settings").
void BM_RhexMujocoVariant(benchmark::State& state) {
  const bench::MujocoVariant variant = bench::rhex_mujoco_variants().at(static_cast<std::size_t>(state.range(0)));
  RhexParams params;
  params.episode.legs = static_cast<rhex::LegModel>(state.range(1));
  bench::apply(variant, params.episode);
  if (!runs(state, params)) return;
  const rhex::EpisodeResult result = time_tripod_episode(state, params);
  state.SetLabel(variant.name + "/" + std::string(enum_to_string(rhex::kLegModelNames, params.episode.legs)));
  state.counters["steps"] = result.walk_steps + result.settle_steps;
}
BENCHMARK(BM_RhexMujocoVariant)
    ->ArgsProduct({benchmark::CreateDenseRange(0, static_cast<int>(bench::rhex_mujoco_variants().size()) - 1, 1), {0, 1}})
    ->ArgNames({"variant", "legs"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

// The compliant legs' cost under the solver options the issue of its speed names (bench/README.md,
// "RHex"): the LCP solver and the plate joints' limit rows, with DART's own collision detector.
void BM_RhexCompliantOptions(benchmark::State& state) {
  RhexParams params;
  params.episode.collision = rhex::CollisionKind::kDart;
  params.episode.legs = rhex::LegModel::kCompliant;
  params.episode.lcp = static_cast<rhex::LcpSolver>(state.range(0));
  params.episode.plate_joint_limits = state.range(1) != 0;
  time_tripod_episode(state, params);
}
BENCHMARK(BM_RhexCompliantOptions)
    ->ArgsProduct({{0, 1}, {1, 0}})
    ->ArgNames({"pgs", "limits"})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

// Random controllers (the first generation of a run) through the evaluator.
void BM_RhexRandomBatch(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const Task task{RhexTask{}};
  constexpr Index kBatch = 64;
  RowMatrix genotypes(kBatch, rhex::kGenes);
  Rng rng(7);
  for (Index i = 0; i < genotypes.size(); ++i) genotypes.data()[i] = static_cast<Real>(rng.uniform());
  EvaluationBatch out;
  out.resize(kBatch, task.base_feature_size());
  auto evaluator = threads == 1 ? make_evaluator(1) : make_thread_evaluator(threads, 1);
  for (auto _ : state) evaluator->evaluate(task, {genotypes.data(), kBatch, rhex::kGenes}, out.view());
  int dead = 0;
  for (auto v : out.valid) dead += v == 0;
  state.counters["episodes_per_s"] = benchmark::Counter(static_cast<double>(kBatch), benchmark::Counter::kIsRate);
  state.counters["dead_fraction"] = static_cast<double>(dead) / kBatch;
}
BENCHMARK(BM_RhexRandomBatch)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

}  // namespace
}  // namespace qdmeta
