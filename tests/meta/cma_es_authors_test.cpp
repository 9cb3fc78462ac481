// The authors' realisation of lambda = 1 (CmaSmallPopulation::kAuthors) against a recombination
// computed here by hand: c-cmaes's default population 4 + floor(3 ln n), mu = lambda / 2, weights
// ln(mu + 1) - ln i, the evaluated sample ranked by its negated meta-fitness against the
// unevaluated samples' 0, equal values latest first (c-cmaes's index sort).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace qdmeta {
namespace {

CmaEsParams authors(int n) {
  CmaEsParams p;
  p.dimension = n;
  p.population_size = 1;
  p.small_population = CmaSmallPopulation::kAuthors;
  return p;
}

// sum_k w_k x_{order[k]} with w_k = ln(mu + 1) - ln k normalised, k = 1 .. mu.
Eigen::VectorXd hand_recombination(const Eigen::MatrixXd& x, const std::vector<int>& order) {
  const double mu = static_cast<double>(order.size());
  std::vector<double> w;
  double sum = 0.0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    w.push_back(std::log(mu + 1.0) - std::log(static_cast<double>(k) + 1.0));
    sum += w.back();
  }
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(x.rows());
  for (std::size_t k = 0; k < order.size(); ++k) mean += (w[k] / sum) * x.col(order[k]);
  return mean;
}

TEST(CmaEsAuthorsLambdaOne, SamplesTheLibraryDefaultPopulation) {
  // K = 222 (Rastrigin): 4 + floor(3 ln 222) = 4 + floor(16.19) = 20, mu = 10.
  const CmaEs cma(authors(222));
  EXPECT_EQ(cma.strategy().lambda, 20);
  EXPECT_EQ(cma.strategy().evaluated, 1);
  EXPECT_EQ(cma.strategy().mu, 10);
  // ln 11 / sum_{i=1..10} (ln 11 - ln i) = 2.397895 / (23.978953 - 15.104413) = 0.270199
  EXPECT_NEAR(cma.strategy().weights(0), 0.270199, 1e-6);
  EXPECT_EQ(CmaEs::sampled_population(authors(542)), 4 + 18);  // 3 ln 542 = 18.88
  // Only a population below 2 is replaced: lambda = 2 and the default (1,1)-ES are unchanged.
  CmaEsParams two = authors(222);
  two.population_size = 2;
  EXPECT_EQ(CmaEs(two).strategy().lambda, 2);
  CmaEsParams one_one = authors(222);
  one_one.small_population = CmaSmallPopulation::kOneOne;
  EXPECT_EQ(CmaEs(one_one).strategy().lambda, 1);
}

struct Case {
  double fitness;          // what tell() receives for sample 0
  CmaObjective objective;
  std::vector<int> order;  // the mu = 3 recombined samples of lambda = 6, best first
};

// K = 2: lambda = 4 + floor(3 ln 2) = 6, mu = 3. A positive meta-fitness (maximised) is a negative
// library value and ranks sample 0 first, then the unevaluated 5, 4; a zero or negative one ties
// with or ranks below the unevaluated 0s, so sample 0 is not recombined at all.
TEST(CmaEsAuthorsLambdaOne, MeanIsTheHandComputedRecombination) {
  const std::vector<Case> cases = {
      {2.5, CmaObjective::kMaximise, {0, 5, 4}},
      {0.0, CmaObjective::kMaximise, {5, 4, 3}},
      {-1.0, CmaObjective::kMaximise, {5, 4, 3}},
      {-1.0, CmaObjective::kMinimise, {0, 5, 4}},
      {3.0, CmaObjective::kMinimise, {5, 4, 3}},
  };
  for (const Case& c : cases) {
    CmaEsParams p = authors(2);
    p.bounds = CmaBoundsHandling::kNone;
    p.x0 = {0.3, -0.2};
    CmaEs cma(p);
    ASSERT_EQ(cma.strategy().lambda, 6);
    Rng rng(11);
    const Eigen::MatrixXd x = cma.ask(rng);
    ASSERT_EQ(x.cols(), 6);
    cma.tell(Eigen::VectorXd::Constant(1, c.fitness), c.objective);
    const Eigen::VectorXd expected = hand_recombination(x, c.order);
    for (int i = 0; i < 2; ++i) EXPECT_NEAR(cma.state().mean(i), expected(i), 1e-12) << "fitness " << c.fitness;
  }
}

// The authors' EA clamped the samples it evaluated; the library recombined the others as drawn.
TEST(CmaEsAuthorsLambdaOne, ClampsOnlyTheEvaluatedSample) {
  CmaEsParams p = authors(4);  // lambda = 4 + floor(3 ln 4) = 8
  p.initial_sigma = 5.0;       // most coordinates fall outside [-1, 1]
  CmaEs cma(p);
  Rng rng(5);
  const Eigen::MatrixXd x = cma.ask(rng);
  ASSERT_EQ(x.cols(), 8);
  EXPECT_LE(x.col(0).cwiseAbs().maxCoeff(), 1.0);
  EXPECT_GT(x.rightCols(7).cwiseAbs().maxCoeff(), 1.0);
  cma.tell(Eigen::VectorXd::Constant(1, 1.0), CmaObjective::kMaximise);
  const Eigen::VectorXd expected = hand_recombination(x, {0, 7, 6, 5});
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(cma.state().mean(i), expected(i), 1e-12);
}

// pycma's recombination of the same 8 samples (tools/pycma_authors_reference.py, pycma 4.5.0,
// seed 3; docs/cma_es.md): given them as the pending candidates, qdmeta's tell() of a positive
// meta-fitness must give pycma's mean.
TEST(CmaEsAuthorsLambdaOne, MeanMatchesPycmasRecombinationOfTheSameSamples) {
  const double samples[8][4] = {
      {0.9943142367151593, 0.31825765345961166, 0.14824994026943308, -0.8317812928255758},
      {-0.03869410125719952, -0.07738170689197163, 0.058628224977323125, -0.21351209489504672},
      {0.07809091551203588, -0.13861199781108247, -0.5569488001960512, 0.5423277772304306},
      {0.540659021103765, 0.9547972167249025, 0.12501744651677515, -0.10234629514424035},
      {-0.1726799738097652, -0.6732483233351161, 0.5911959968755045, -0.4505544604609013},
      {-0.49252326351008646, -0.002826235031175156, 0.8430927546239462, 0.21836257212668825},
      {-0.4118925699632341, -0.25650105629137676, 0.41263029874118706, 0.019740308724547115},
      {-0.284418175159615, -0.01501679883996937, 0.47253744652243146, 1.08809244433507},
  };
  const double pycma_mean[4] = {0.31271874846906117, 0.11252521918463024, 0.3284027101603587, -0.08678143978311417};
  CmaEsParams p = authors(4);
  p.bounds = CmaBoundsHandling::kNone;
  p.initial_mean = 0.1;
  p.initial_sigma = 0.5;
  CmaEs cma(p);
  CmaEsState state = cma.state();
  state.samples.resize(4, 8);
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 4; ++i) state.samples(i, k) = samples[k][i];
  state.awaiting_tell = true;
  cma.set_state(state);
  cma.tell(Eigen::VectorXd::Constant(1, 0.7), CmaObjective::kMaximise);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(cma.state().mean(i), pycma_mean[i], 1e-14);
}

TEST(CmaEsAuthorsLambdaOne, TellTakesTheEvaluatedFitnessOnly) {
  CmaEs cma(authors(222));
  Rng rng(1);
  cma.ask(rng);
  EXPECT_INPUT_ERROR(cma.tell(Eigen::VectorXd::Zero(20), CmaObjective::kMaximise),
                     "CmaEs::tell: expected 1 fitness values, got 20");
  cma.tell(Eigen::VectorXd::Constant(1, 4.0), CmaObjective::kMaximise);
  EXPECT_EQ(cma.state().evaluations, 20);
  // A checkpoint of this state loads back (its samples are n x 20).
  CmaEs other(authors(222));
  other.set_state(cma.state());
  EXPECT_TRUE(other.state() == cma.state());
}

}  // namespace
}  // namespace qdmeta
