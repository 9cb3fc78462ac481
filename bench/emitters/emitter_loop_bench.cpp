// One iteration of the CMA-MAE paper's loop as bench/peers/cma_peer runs it: 15 evolution-strategy
// emitters of batch 36 on the 100-D linear-projection sphere, a 100 x 100 grid, alpha 0.01
// (ask, evaluate, tell). Args (gap, threads): gap 0, CMA-ES decomposes C at the tutorial's gap
// (after every generation at this size, as before the emitters had a gap of their own); gap 1,
// pyribs's gap, the emitters' default (every third generation); threads, the task arena the
// loop runs in (the scheduler tells the 15 emitters at once on it). Each benchmark first runs
// 200 iterations untimed, so that the archive and the emitters are past their start.
// BM_EvolutionStrategyAskTell: one emitter's evolution strategy alone, ask + tell_ranked of a
// batch of 36 with 18 parents on the sphere, Args (n, es): es 0 the full CMA-ES at pyribs's
// eigen gap (decompositions amortised), 1 the separable one (meta/sep_cma_es.hpp).
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "peers/cma_domains.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "qdmeta/meta/cma_es.hpp"
#include "qdmeta/meta/sep_cma_es.hpp"

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
  tbb::task_arena arena(static_cast<int>(state.range(1)));
  arena.execute([&] {
    for (int i = 0; i < 200; ++i) iterate();
    for (auto _ : state) iterate();
  });
  state.SetItemsProcessed(state.iterations() * scheduler.batch_size());
}
BENCHMARK(BM_CmaMaeSphereIteration)
    ->Args({0, 1})
    ->Args({1, 1})
    ->Args({1, 2})
    ->Args({1, 4})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

template <class Es>
void ask_tell_loop(benchmark::State& state, Es& es) {
  Rng rng(1);
  const int lambda = es.strategy().lambda;
  std::vector<double> f(static_cast<std::size_t>(lambda));
  std::vector<int> order(static_cast<std::size_t>(lambda));
  const auto cycle = [&] {
    const Eigen::MatrixXd& x = es.ask(rng);
    for (int k = 0; k < lambda; ++k) f[static_cast<std::size_t>(k)] = x.col(k).squaredNorm();
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&f](int a, int b) { return f[static_cast<std::size_t>(a)] < f[static_cast<std::size_t>(b)]; });
    es.tell_ranked(order, lambda / 2);
  };
  for (int i = 0; i < 20; ++i) cycle();
  const auto decompositions = [&es] {
    if constexpr (requires { es.state().decompositions; }) return static_cast<double>(es.state().decompositions);
    return 0.0;
  };
  const double before = decompositions();
  for (auto _ : state) cycle();
  state.SetItemsProcessed(state.iterations() * lambda);
  state.counters["decompositions"] = decompositions() - before;
}

void BM_EvolutionStrategyAskTell(benchmark::State& state) {
  CmaEsParams p;
  p.dimension = static_cast<int>(state.range(0));
  p.population_size = 36;
  p.initial_sigma = 0.5;
  p.initial_mean = 1.0;
  p.bounds = CmaBoundsHandling::kNone;
  p.eigen_gap = CmaEigenGap::kPurecma;
  if (state.range(1) == 0) {
    CmaEs es(p);
    ask_tell_loop(state, es);
  } else {
    SepCmaEs es(p);
    ask_tell_loop(state, es);
  }
}
BENCHMARK(BM_EvolutionStrategyAskTell)->Args({100, 0})->Args({100, 1})->Args({1000, 1})->Unit(benchmark::kMicrosecond);
// The full ES at n = 1000 decomposes C about every 28 generations (pyribs's gap): 84 timed
// generations hold 3 decompositions, so the figure is amortised over them.
BENCHMARK(BM_EvolutionStrategyAskTell)->Args({1000, 0})->Iterations(84)->Unit(benchmark::kMicrosecond);

}  // namespace
