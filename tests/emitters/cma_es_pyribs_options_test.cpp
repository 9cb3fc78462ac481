// Tests of the CMA-ES options the emitters have for pyribs's sake (src/qdmeta/meta/cma_es.hpp):
// eigen_gap "purecma", the emitters' gap between eigendecompositions, is pycma's purecma and
// pyribs's 0.5 lambda / ((c1 + c_mu) n) for floor(lambda / 2) parents, whatever the parents of
// each update; rank_one "pyribs" is pyribs 0.12's rank-one term. The defaults stay QD-Meta's.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace qdmeta {
namespace {

// pyribs 0.12's lazy_gap_evals (emitters/opt/_cma_es.py), recomputed here from its formulas.
double pyribs_gap(int n, int lambda) {
  const int mu = lambda / 2;
  std::vector<double> w(static_cast<std::size_t>(mu));
  for (int i = 0; i < mu; ++i) w[static_cast<std::size_t>(i)] = std::log(mu + 0.5) - std::log(i + 1.0);
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  double squares = 0.0;
  for (double& x : w) {
    x /= total;
    squares += x * x;
  }
  const double mueff = 1.0 / squares;
  const double c1 = 2.0 / ((n + 1.3) * (n + 1.3) + mueff);
  const double cmu = std::min(1.0 - c1, 2.0 * (mueff - 2.0 + 1.0 / mueff) / ((n + 2.0) * (n + 2.0) + mueff));
  return 0.5 * n * lambda / (c1 + cmu) / (static_cast<double>(n) * n);
}

CmaEsParams pyribs_cma_params(int n, int lambda, CmaEigenGap gap) {
  CmaEsParams p;
  p.dimension = n;
  p.population_size = lambda;
  p.initial_sigma = 0.5;
  p.bounds = CmaBoundsHandling::kNone;
  p.eigen_gap = gap;
  return p;
}

// Runs `generations` ask/tell_ranked cycles on the sphere with `parents` parents each.
CmaEs run_pyribs_cma(const CmaEsParams& p, int generations, int parents) {
  CmaEs cma(p);
  Rng rng(7);
  std::vector<int> order(static_cast<std::size_t>(p.population_size));
  for (int g = 0; g < generations; ++g) {
    const Eigen::MatrixXd& x = cma.ask(rng);
    const Eigen::VectorXd f = x.colwise().squaredNorm().transpose();
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&f](int a, int b) { return f(a) < f(b); });
    cma.tell_ranked(order, parents);
  }
  return cma;
}

// Every name of an option's table is its value's to_string and parses back to it.
template <class Table, class Parse>
void expect_names_round_trip(const Table& table, Parse parse) {
  for (const auto& [value, name] : table) {
    EXPECT_EQ(to_string(value), name);
    EXPECT_EQ(parse(name), value);
  }
}

TEST(CmaEsEigenGap, PurecmaIsPyribsGapAtTheCmaMaePapersSize) {
  const CmaEs cma(pyribs_cma_params(100, 36, CmaEigenGap::kPurecma));
  EXPECT_NEAR(cma.strategy().eigen_interval, pyribs_gap(100, 36), 1e-9 * pyribs_gap(100, 36));
  // About 103 evaluations: C is decomposed after every third generation of 36, not every one.
  EXPECT_GT(cma.strategy().eigen_interval, 72.0);
  EXPECT_LT(cma.strategy().eigen_interval, 108.0);
  const CmaEs tutorial(pyribs_cma_params(100, 36, CmaEigenGap::kTutorial));
  EXPECT_LT(tutorial.strategy().eigen_interval, 36.0);
}

TEST(CmaEsEigenGap, PurecmaDecomposesEveryThirdGenerationWhateverTheParents) {
  // Decompositions after generations 3, 6, ..., 30 for any parent count; the tutorial's gap,
  // recomputed from each update's rates, decomposes after every generation with half the batch.
  for (const int parents : {18, 5, 36}) {
    const CmaEs cma = run_pyribs_cma(pyribs_cma_params(100, 36, CmaEigenGap::kPurecma), 30, parents);
    EXPECT_EQ(cma.state().decompositions, 10) << parents;
    EXPECT_EQ(cma.state().eigen_evaluations, 30 * 36) << parents;
  }
  EXPECT_EQ(run_pyribs_cma(pyribs_cma_params(100, 36, CmaEigenGap::kTutorial), 30, 18).state().decompositions, 30);
}

TEST(CmaEsEigenGap, BAndDAreThoseOfTheCovarianceAtTheLastDecomposition) {
  // In 20-D with lambda = 12 the gap is about 24 evaluations: a decomposition after every second
  // generation. After 60 generations B D^2 B^T is C; one generation later C has moved on.
  const CmaEsParams p = pyribs_cma_params(20, 12, CmaEigenGap::kPurecma);
  ASSERT_NEAR(CmaEs(p).strategy().eigen_interval, pyribs_gap(20, 12), 1e-9 * pyribs_gap(20, 12));
  ASSERT_GT(CmaEs(p).strategy().eigen_interval, 12.0);
  ASSERT_LT(CmaEs(p).strategy().eigen_interval, 24.0);
  const auto rebuilt = [](const CmaEsState& s) { return Eigen::MatrixXd(s.B * s.D.cwiseAbs2().asDiagonal() * s.B.transpose()); };
  const CmaEs even = run_pyribs_cma(p, 60, 6);
  EXPECT_EQ(even.state().decompositions, 30);
  EXPECT_TRUE(rebuilt(even.state()).isApprox(even.state().C, 1e-10));
  const CmaEs odd = run_pyribs_cma(p, 61, 6);
  EXPECT_EQ(odd.state().eigen_evaluations, 60 * 12);
  EXPECT_FALSE(rebuilt(odd.state()).isApprox(odd.state().C, 1e-6));
  EXPECT_TRUE(rebuilt(odd.state()).isApprox(even.state().C, 1e-10));
}

TEST(CmaEsEigenGap, NamesRoundTripAndBadValuesAreRefused) {
  expect_names_round_trip(kCmaEigenGapNames, cma_eigen_gap_from_string);
  EXPECT_INPUT_ERROR(cma_eigen_gap_from_string("lazy"),
                     "CMA-ES eigen gap = \"lazy\" is not a valid choice: use one of \"tutorial\", \"purecma\"");
  CmaEsParams p = pyribs_cma_params(3, 4, static_cast<CmaEigenGap>(7));
  EXPECT_INPUT_ERROR(p.validate(), "CmaEsParams.eigen_gap = 7 is invalid: must be one of tutorial, purecma");
  EXPECT_EQ(CmaEsParams{}.eigen_gap, CmaEigenGap::kTutorial);  // QD-Meta's, unchanged
}

TEST(CmaEsEigenGap, EmittersUsePurecmaUnlessTold) {
  EvolutionStrategyEmitterParams p;
  p.x0.assign(4, 0.0);
  EXPECT_EQ(EvolutionStrategyEmitter(p, {}).optimiser().params().eigen_gap, CmaEigenGap::kPurecma);
  p.eigen_gap = CmaEigenGap::kTutorial;
  EXPECT_EQ(EvolutionStrategyEmitter(p, {}).optimiser().params().eigen_gap, CmaEigenGap::kTutorial);
}

TEST(CmaEsRankOne, PyribsTermIsC1SquaredTimesTheUnnormalisedPath) {
  // One generation from the same samples: pyribs's p_c is sigma0 times the tutorial's, and its
  // C differs from the tutorial's by (c1^2 sigma0^2 - c1) p_c p_c^T (tutorial's p_c) alone.
  CmaEsParams p = pyribs_cma_params(6, 10, CmaEigenGap::kTutorial);
  const CmaEs tutorial = run_pyribs_cma(p, 1, 5);
  p.rank_one = CmaRankOne::kPyribs;
  const CmaEs pyribs = run_pyribs_cma(p, 1, 5);
  const CmaEsState& t = tutorial.state();
  const CmaEsState& r = pyribs.state();
  ASSERT_GT(t.p_c.norm(), 0.1);  // h_sigma held: the path moved
  EXPECT_TRUE(r.mean == t.mean);
  EXPECT_EQ(r.sigma, t.sigma);
  EXPECT_TRUE(r.p_c.isApprox(p.initial_sigma * t.p_c, 1e-15));
  const double c1 = tutorial.strategy().c1;
  const double s0 = p.initial_sigma;
  const Eigen::MatrixXd expected = t.C + (c1 * c1 * s0 * s0 - c1) * t.p_c * t.p_c.transpose();
  EXPECT_TRUE(r.C.isApprox(expected, 1e-14));
  EXPECT_FALSE(r.C.isApprox(t.C, 1e-6));
}

TEST(CmaEsRankOne, NamesRoundTripAndBadValuesAreRefused) {
  expect_names_round_trip(kCmaRankOneNames, cma_rank_one_from_string);
  EXPECT_INPUT_ERROR(cma_rank_one_from_string("none"),
                     "CMA-ES rank-one term = \"none\" is not a valid choice: use one of \"tutorial\", \"pyribs\"");
  CmaEsParams p = pyribs_cma_params(3, 4, CmaEigenGap::kTutorial);
  p.rank_one = static_cast<CmaRankOne>(5);
  EXPECT_INPUT_ERROR(p.validate(), "CmaEsParams.rank_one = 5 is invalid: must be one of tutorial, pyribs");
  EXPECT_EQ(CmaEsParams{}.rank_one, CmaRankOne::kTutorial);
  EXPECT_EQ(EvolutionStrategyEmitterParams{}.rank_one, CmaRankOne::kTutorial);
}

}  // namespace
}  // namespace qdmeta
