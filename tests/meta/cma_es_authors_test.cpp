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
