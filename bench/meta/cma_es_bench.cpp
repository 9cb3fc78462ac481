// One ask + tell cycle of qdmeta::CmaEs at the meta-genotype sizes of QD-Meta
// (K = 222 and K = 542 feature-map weights, lambda = 10; neural_feature_map.hpp's
// N_h N_b + 1 + N_t N_h + 1 for 20 -> 10 -> 2 and 50 -> 10 -> 4). The time per iteration is amortised
// over the lazy eigendecompositions (one every ceil(interval / lambda) generations);
// BM_CmaEsDecompose measures one decomposition alone, qdmeta::symmetric_eigen (what CmaEs
// runs: fixed-order sums, the same bits on every CPU) against Eigen's SelfAdjointEigenSolver
// (vectorised for the CPU it is built on; what CmaEs ran before), on the same matrix.
#include "qdmeta/core/eigen.hpp"  // before Eigen/Dense: Eigen configured as in the library

// GCC 12 false -Wmaybe-uninitialized inside Eigen 3.4's SelfAdjointEigenSolver.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/Dense>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <benchmark/benchmark.h>

#include <random>

#include "qdmeta/meta/cma_es.hpp"
#include "qdmeta/meta/symmetric_eigen.hpp"

namespace {

qdmeta::CmaEsParams params_for(benchmark::State& state) {
  qdmeta::CmaEsParams p;
  p.dimension = static_cast<int>(state.range(0));
  p.population_size = 10;
  return p;
}

void BM_CmaEsAskTell(benchmark::State& state) {
  qdmeta::CmaEs cma(params_for(state));
  std::mt19937_64 rng(1);
  Eigen::VectorXd fitness(10);
  for (auto _ : state) {
    const Eigen::MatrixXd& x = cma.ask(rng);
    fitness = x.colwise().squaredNorm().transpose();
    cma.tell(fitness, qdmeta::CmaObjective::kMaximise);
  }
  state.counters["decompositions_per_cycle"] = benchmark::Counter(
      static_cast<double>(cma.state().decompositions) /
      static_cast<double>(cma.state().generation));
}
BENCHMARK(BM_CmaEsAskTell)->Arg(222)->Arg(542)->Unit(benchmark::kMicrosecond);

// QD-Meta's sampling: normals from qdmeta::Rng, either through the bulk overload ask(Rng&)
// (Arg 1 = 1) or one std::function call per draw (0), the form QD-Meta used before; both give
// the same bits. Frozen, so tell() costs nothing and the time is ask()'s alone.
void BM_CmaEsAskFrozen(benchmark::State& state) {
  qdmeta::CmaEsParams p = params_for(state);
  p.frozen = true;
  qdmeta::CmaEs cma(p);
  qdmeta::Rng rng(1);
  const bool bulk = state.range(1) == 1;
  const Eigen::VectorXd fitness = Eigen::VectorXd::Zero(10);
  for (auto _ : state) {
    const Eigen::MatrixXd& x = bulk ? cma.ask(rng) : cma.ask([&rng] { return rng.normal(); });
    benchmark::DoNotOptimize(x.data());
    cma.tell(fitness, qdmeta::CmaObjective::kMaximise);
  }
}
BENCHMARK(BM_CmaEsAskFrozen)->Args({222, 0})->Args({222, 1})->Args({542, 0})->Args({542, 1})
    ->Unit(benchmark::kMicrosecond);

// One ask + tell as QD-Meta runs it (normals from qdmeta::Rng in bulk).
void BM_CmaEsAskTellRng(benchmark::State& state) {
  qdmeta::CmaEs cma(params_for(state));
  qdmeta::Rng rng(1);
  Eigen::VectorXd fitness(10);
  for (auto _ : state) {
    const Eigen::MatrixXd& x = cma.ask(rng);
    fitness = x.colwise().squaredNorm().transpose();
    cma.tell(fitness, qdmeta::CmaObjective::kMaximise);
  }
}
BENCHMARK(BM_CmaEsAskTellRng)->Arg(222)->Arg(542)->Unit(benchmark::kMicrosecond);

Eigen::MatrixXd covariance_for(benchmark::State& state) {
  const Eigen::Index n = state.range(0);
  std::mt19937_64 rng(2);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(n, n);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
  return a * a.transpose() / static_cast<double>(n) + Eigen::MatrixXd::Identity(n, n);
}

void BM_CmaEsDecompose(benchmark::State& state) {
  const Eigen::MatrixXd c = covariance_for(state);
  for (auto _ : state) {
    const qdmeta::SymmetricEigen eigen = qdmeta::symmetric_eigen(c);
    benchmark::DoNotOptimize(eigen.values.data());
  }
}
BENCHMARK(BM_CmaEsDecompose)->Arg(100)->Arg(222)->Arg(542)->Unit(benchmark::kMillisecond);

void BM_EigenSelfAdjointSolver(benchmark::State& state) {
  const Eigen::MatrixXd c = covariance_for(state);
  for (auto _ : state) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(c);
    benchmark::DoNotOptimize(solver.eigenvalues().data());
  }
}
BENCHMARK(BM_EigenSelfAdjointSolver)->Arg(100)->Arg(222)->Arg(542)->Unit(benchmark::kMillisecond);

}  // namespace
