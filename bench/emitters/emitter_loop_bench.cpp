// One iteration of the CMA-MAE paper's loop as bench/peers/cma_peer runs it: 15 evolution-strategy
// emitters of batch 36 on the 100-D linear-projection sphere, a 100 x 100 grid, alpha 0.01
// (ask, evaluate, tell). Arg 0: CMA-ES decomposes C at the tutorial's gap (after every
// generation at this size, as before the emitters had a gap of their own); Arg 1: pyribs's
// gap, the emitters' default (every third generation). Each benchmark first runs 200
// iterations untimed, so that the archive and the emitters are past their start.
#include <benchmark/benchmark.h>

#include <vector>

#include "peers/cma_domains.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace {

using namespace qdmeta;

void BM_CmaMaeSphereIteration(benchmark::State& state) {
  constexpr Index kGenes = 100;
  const peers::CmaDomain domain = peers::lin_proj_sphere_domain(kGenes);
  GridArchiveParams grid;
  grid.bins = {100, 100};
  grid.lower = -domain.measure_bound;
  grid.upper = domain.measure_bound;
  grid.solution_size = kGenes;
  GridArchive archive(grid);
  EvolutionStrategyEmitterParams ep;
  ep.x0.assign(kGenes, 0.0);
  ep.sigma0 = domain.sigma0;
  ep.batch_size = 36;
  ep.ranker = EmitterRanker::kImprovement;
  ep.selection = EmitterSelection::kMu;
  ep.restart = EmitterRestart::kBasic;
  ep.eigen_gap = state.range(0) == 0 ? CmaEigenGap::kTutorial : CmaEigenGap::kPurecma;
  Scheduler scheduler(archive, ThresholdParams{0.01, 0.0}, make_evolution_strategy_emitters(archive, ep, 15));
  Rng rng(1);
  std::vector<Real> objectives;
  RowMatrix measures;
  const auto iterate = [&] {
    const RowMatrix& x = scheduler.ask(rng);
    peers::evaluate_rows(x, peers::lin_proj_sphere, objectives, measures);
    scheduler.tell(objectives, measures);
  };
  for (int i = 0; i < 200; ++i) iterate();
  for (auto _ : state) iterate();
  state.SetItemsProcessed(state.iterations() * scheduler.batch_size());
}
BENCHMARK(BM_CmaMaeSphereIteration)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
