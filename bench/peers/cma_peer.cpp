// qdmeta's side of the CMA-MAE paper's comparison (bench/peers/README.md, "CMA-ME and CMA-MAE"):
// CMA-ME or CMA-MAE on the linear-projection sphere or the planar arm (cma_domains.hpp) with the
// paper's settings, driven through the emitter scheduler (qdmeta/emitters/scheduler.hpp) as
// pyribs's Scheduler is driven in peer_pyribs_cma.py. Prints one JSON line, the fields of the
// Python runners' (common.emit).
//
//   cma_peer --domain sphere|arm --algorithm cma-me|cma-mae [--iterations 10000] [--seed 1]
//            [--genes 100] [--eigen-gap purecma|tutorial]
//            [--rank-one tutorial|pyribs] [--add-mode single|batch] [--threads 1]
//
// --threads: the task arena the loop runs in (the scheduler tells its emitters at once on it);
// 1, the default, is the comparison's (pyribs runs on one thread).
//
// --add-mode batch runs pyribs's Scheduler default (every row against the thresholds before the
// batch); qdmeta's default is single (rows one at a time, in order), docs/fidelity.md.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <string_view>

#include <tbb/task_arena.h>

#include <fmt/format.h>

#include "cma_domains.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace {

using namespace qdmeta;
using Clock = std::chrono::steady_clock;

constexpr int kEmitters = 15;
constexpr int kEmitterBatch = 36;
constexpr int kGridBins = 100;

struct Options {
  std::string domain = "sphere";
  std::string algorithm = "cma-mae";
  long iterations = 10'000;
  std::uint64_t seed = 1;
  Index genes = 100;
  CmaEigenGap eigen_gap = CmaEigenGap::kPurecma;  // the emitters' default, pyribs's gap
  CmaRankOne rank_one = CmaRankOne::kTutorial;     // "pyribs": pyribs 0.12's term (fidelity.md)
  AddMode add_mode = AddMode::kSingle;             // "batch": pyribs's Scheduler default
  int threads = 1;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view key = argv[i];
    if (i + 1 >= argc) throw InputError(fmt::format("cma_peer: {} needs a value", key));
    const char* value = argv[++i];
    if (key == "--domain") o.domain = value;
    else if (key == "--algorithm") o.algorithm = value;
    else if (key == "--iterations") o.iterations = std::atol(value);
    else if (key == "--seed") o.seed = std::strtoull(value, nullptr, 10);
    else if (key == "--genes") o.genes = std::atol(value);
    else if (key == "--eigen-gap") o.eigen_gap = cma_eigen_gap_from_string(value);
    else if (key == "--rank-one") o.rank_one = cma_rank_one_from_string(value);
    else if (key == "--add-mode") o.add_mode = enum_from_string(kAddModeNames, "cma_peer --add-mode", value);
    else if (key == "--threads") o.threads = std::atoi(value);
    else throw InputError(fmt::format("cma_peer: unknown option {}", key));
  }
  if (o.domain != "sphere" && o.domain != "arm") throw InputError(fmt::format("cma_peer --domain = {}: sphere or arm", o.domain));
  if (o.algorithm != "cma-me" && o.algorithm != "cma-mae") {
    throw InputError(fmt::format("cma_peer --algorithm = {}: cma-me or cma-mae", o.algorithm));
  }
  if (o.iterations < 1 || o.genes < 2) throw InputError("cma_peer: --iterations must be >= 1 and --genes >= 2");
  if (o.threads < 1) throw InputError("cma_peer: --threads must be >= 1");
  return o;
}

// CMA-ME as the paper's baseline (two-stage improvement, mu, basic restarts, alpha 1); CMA-MAE
// with the improvement ranker, alpha 0.01 and threshold_min 0 (pyribs's sphere example).
template <class Evaluate>
int run(const Options& o, const peers::CmaDomain& domain, Evaluate evaluate_one) {
  GridArchiveParams grid;
  grid.bins = {kGridBins, kGridBins};
  grid.lower = -domain.measure_bound;
  grid.upper = domain.measure_bound;
  grid.solution_size = o.genes;
  GridArchive archive(grid);
  const bool mae = o.algorithm == "cma-mae";
  EvolutionStrategyEmitterParams ep;
  ep.x0.assign(static_cast<std::size_t>(o.genes), 0.0);
  ep.sigma0 = domain.sigma0;
  ep.batch_size = kEmitterBatch;
  ep.ranker = mae ? EmitterRanker::kImprovement : EmitterRanker::kTwoStageImprovement;
  ep.selection = EmitterSelection::kMu;
  ep.restart = EmitterRestart::kBasic;
  ep.eigen_gap = o.eigen_gap;
  ep.rank_one = o.rank_one;
  ThresholdParams thresholds;
  thresholds.alpha = mae ? 0.01 : 1.0;
  thresholds.threshold_min = mae ? 0.0 : -std::numeric_limits<double>::infinity();
  Scheduler scheduler(archive, thresholds, make_evolution_strategy_emitters(archive, ep, kEmitters), o.add_mode);
  Rng rng(o.seed);
  std::vector<Real> objectives;
  RowMatrix measures;
  double task_s = 0.0, obj_max = -std::numeric_limits<double>::infinity();
  const auto start = Clock::now();
  tbb::task_arena arena(o.threads);
  arena.execute([&] {
    for (long it = 0; it < o.iterations; ++it) {
      const RowMatrix& x = scheduler.ask(rng);
      const auto task_start = Clock::now();
      peers::evaluate_rows(x, evaluate_one, objectives, measures);
      task_s += std::chrono::duration<double>(Clock::now() - task_start).count();
      for (Real f : objectives) obj_max = std::max(obj_max, static_cast<double>(f));
      scheduler.tell(objectives, measures);
    }
  });
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const ArchiveStats stats = archive.stats();
  const long evals = o.iterations * scheduler.batch_size();
  // The paper's QD-score: the sum of the elites' objectives over all cells; coverage in percent.
  fmt::print(R"({{"library": "qdmeta", "version": "{}", "algorithm": "{}", "domain": "{}", "iterations": {}, )"
             R"("evals": {}, "wall_s": {}, "task_s": {}, "num_elites": {}, "qd_score": {}, "coverage": {}, )"
             R"("obj_max": {}, "seed": {}, "note": "C++ emitters (scheduler.hpp), {}, eigen gap {}, rank-one {}, add mode {}"}})"
             "\n",
             kVersion, o.algorithm, domain.name, o.iterations, evals, wall, task_s, stats.num_elites,
             stats.qd_score / static_cast<double>(archive.cells()), 100.0 * stats.coverage, obj_max, o.seed,
             o.threads == 1 ? std::string("one thread") : fmt::format("{} threads", o.threads), to_string(o.eigen_gap), to_string(o.rank_one), to_string(o.add_mode));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    if (o.domain == "sphere") return run(o, peers::lin_proj_sphere_domain(o.genes), peers::lin_proj_sphere);
    return run(o, peers::arm_domain(o.genes), peers::arm);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
