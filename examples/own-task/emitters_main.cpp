// arm-emitters: CMA-MAE on the planar arm through the C++ emitter API (docs/library.md,
// "Emitters"), two ways: a Scheduler driven by hand with mixed emitters, and qdmeta::CmaMae, the
// algorithm behind `algorithm = "cma-mae"`, stepped with the library's evaluator. Exits 1 unless
// the hand-driven archive fills and the same seed gives the same archive, and unless the
// algorithm gives the same elites with 1 and 2 threads.
#include <qdmeta/algorithms/cma_mae.hpp>
#include <qdmeta/archive/grid_archive.hpp>
#include <qdmeta/core/evaluation_batch.hpp>
#include <qdmeta/emitters/gaussian_emitter.hpp>
#include <qdmeta/emitters/scheduler.hpp>
#include <qdmeta/eval/evaluator.hpp>
#include <qdmeta/featuremap/select_feature_map.hpp>

#include <cstdio>
#include <exception>
#include <memory>
#include <utility>
#include <vector>

#include "arm_task.hpp"

namespace {

// A 50 x 50 grid over the end effector's (x, y), the arm's base features in [0, 1].
qdmeta::GridArchiveParams arm_grid(const qdmeta::Task& task) {
  qdmeta::GridArchiveParams grid;
  grid.bins = {50, 50};
  grid.solution_size = task.genotype_size();
  grid.qd_offset = task.qd_offset();
  return grid;
}

// The CMA-MAE paper's emitter: improvement ranker, mu selection, basic restarts.
qdmeta::EvolutionStrategyEmitterParams cma_mae_emitter(const qdmeta::Task& task) {
  qdmeta::EvolutionStrategyEmitterParams es;
  es.x0.assign(static_cast<std::size_t>(task.genotype_size()), arm::kStraightGene);
  es.sigma0 = 0.05;
  es.batch_size = 36;
  es.ranker = qdmeta::EmitterRanker::kImprovement;
  es.selection = qdmeta::EmitterSelection::kMu;
  es.restart = qdmeta::EmitterRestart::kBasic;
  es.bounds = qdmeta::CmaBoundsHandling::kResample;  // genes stay in [0, 1]
  es.lower_bound = 0.0;
  es.upper_bound = 1.0;
  return es;
}

qdmeta::ArchiveStats scheduler_by_hand(const qdmeta::Task& task, std::uint64_t seed, int iterations) {
  qdmeta::GridArchive archive(arm_grid(task));
  const qdmeta::EvolutionStrategyEmitterParams es = cma_mae_emitter(task);
  auto emitters = qdmeta::make_evolution_strategy_emitters(archive, es, 4);
  // Emitters may differ: MAP-Elites's Gaussian variation beside the four CMA-ES.
  const qdmeta::GaussianEmitterParams gaussian{.x0 = es.x0, .sigma = 0.05, .batch_size = 36,
                                               .lower_bound = 0.0, .upper_bound = 1.0};
  emitters.push_back(std::make_unique<qdmeta::GaussianEmitter>(gaussian, qdmeta::elite_picker(archive)));
  // Learning rate 0.01, and a cell never reached starts at the task's lowest fitness.
  qdmeta::Scheduler scheduler(archive, qdmeta::ThresholdParams{0.01, task.qd_offset()}, std::move(emitters));

  qdmeta::Rng rng(seed);
  qdmeta::EvaluationBatch results;
  for (int i = 0; i < iterations; ++i) {
    const qdmeta::RowMatrix& x = scheduler.ask(rng);  // 5 x 36 rows
    results.resize(x.rows(), task.base_feature_size());
    task.evaluate({x.data(), x.rows(), x.cols()}, results.view());
    scheduler.tell({results.fitness.data(), static_cast<std::size_t>(x.rows())}, results.base_features,
                   results.valid);
  }
  return archive.stats();
}

qdmeta::EliteTable cma_mae_algorithm(const qdmeta::Task& task, std::uint64_t seed, int steps, int threads) {
  qdmeta::CmaMaeParams p;
  p.emitters = 4;
  p.emitter = cma_mae_emitter(task);
  p.thresholds = {0.01, task.qd_offset()};
  const qdmeta::GridArchiveParams grid = arm_grid(task);
  auto measures = std::make_unique<qdmeta::SelectFeatureMap>(2, std::vector<int>{0, 1});  // (x, y)
  qdmeta::CmaMae<qdmeta::GridArchive> algorithm(p, task, std::move(measures),
                                                [grid](qdmeta::Evaluator*) { return qdmeta::GridArchive(grid); }, seed);
  const auto evaluator = qdmeta::make_evaluator(threads);
  for (int s = 0; s < steps; ++s) algorithm.step(*evaluator);
  return algorithm.elites();
}

}  // namespace

int main() {
  try {
    const qdmeta::Task task(arm::ArmTask(10));
    const qdmeta::ArchiveStats a = scheduler_by_hand(task, 1, 300);
    const qdmeta::ArchiveStats b = scheduler_by_hand(task, 1, 300);
    std::printf("scheduler by hand: %ld elites, coverage %.3f, QD-score %.2f\n", static_cast<long>(a.num_elites),
                a.coverage, a.qd_score);
    const qdmeta::EliteTable one = cma_mae_algorithm(task, 1, 100, 1);
    const qdmeta::EliteTable two = cma_mae_algorithm(task, 1, 100, 2);
    std::printf("qdmeta::CmaMae: %ld elites after 100 steps\n", static_cast<long>(one.size()));
    const bool same_threads = one.index == two.index && one.objective == two.objective && one.solutions == two.solutions;
    if (a.num_elites < 250 || a.qd_score != b.qd_score || a.num_elites != b.num_elites || one.size() < 100 ||
        !same_threads) {
      std::fprintf(stderr, "arm-emitters: unexpected results (same bits across threads: %d)\n", same_threads);
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arm-emitters: %s\n", e.what());
    return 2;
  }
}
