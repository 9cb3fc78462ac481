// Tests of CmaEs::tell_ranked (src/qdmeta/meta/cma_es.hpp), the update the emitters use: with
// half the batch as parents it is CmaEs::tell bit for bit; other parent counts reweight.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace qdmeta {
namespace {

CmaEsParams ranked_cma_params(int lambda) {
  CmaEsParams p;
  p.dimension = 5;
  p.population_size = lambda;
  p.initial_sigma = 0.3;
  p.bounds = CmaBoundsHandling::kNone;
  return p;
}

Eigen::VectorXd sphere(const Eigen::MatrixXd& x) {
  Eigen::VectorXd f(x.cols());
  for (Eigen::Index k = 0; k < x.cols(); ++k) f(k) = (x.col(k).array() - 0.7).square().sum();
  return f;
}

std::vector<int> ascending_order(const Eigen::VectorXd& f) {
  std::vector<int> order(static_cast<std::size_t>(f.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&f](int a, int b) { return f(a) < f(b); });
  return order;
}

TEST(CmaEsRanked, HalfTheBatchAsParentsIsTellBitForBit) {
  for (const int lambda : {6, 12}) {
    CmaEs by_fitness(ranked_cma_params(lambda)), by_order(ranked_cma_params(lambda));
    Rng a(11), b(11);
    for (int g = 0; g < 60; ++g) {  // past several eigendecompositions
      const Eigen::VectorXd f = sphere(by_fitness.ask(a));
      by_order.ask(b);
      by_fitness.tell(f, CmaObjective::kMinimise);
      by_order.tell_ranked(ascending_order(f), lambda / 2);
      ASSERT_TRUE(by_fitness.state() == by_order.state()) << "lambda " << lambda << " generation " << g;
    }
    EXPECT_GT(by_order.state().decompositions, 2);
  }
}

TEST(CmaEsRanked, OtherParentCountsReweightAndZeroOnlyClosesTheAsk) {
  CmaEs half(ranked_cma_params(8)), all(ranked_cma_params(8)), none(ranked_cma_params(8));
  Rng a(5), b(5), c(5);
  const Eigen::VectorXd f = sphere(half.ask(a));
  all.ask(b);
  none.ask(c);
  half.tell_ranked(ascending_order(f), 4);
  all.tell_ranked(ascending_order(f), 8);
  none.tell_ranked(ascending_order(f), 0);
  EXPECT_FALSE(half.state().mean == all.state().mean);
  CmaEsState expected = CmaEs::initial_state(ranked_cma_params(8));
  expected.samples = none.state().samples;
  expected.generation = 1;
  expected.evaluations = 8;
  EXPECT_TRUE(none.state() == expected);
}

TEST(CmaEsRanked, RefusesABadOrderOrParentCount) {
  CmaEs cma(ranked_cma_params(4));
  EXPECT_INPUT_ERROR(cma.tell_ranked(std::vector<int>{0, 1, 2, 3}, 2),
                     "CmaEs::tell_ranked: called without a pending ask; call ask() first");
  Rng rng(1);
  cma.ask(rng);
  EXPECT_INPUT_ERROR(cma.tell_ranked(std::vector<int>{0, 1, 2}, 2),
                     "CmaEs::tell_ranked: expected an order of 4 candidates, got 3");
  EXPECT_INPUT_ERROR(cma.tell_ranked(std::vector<int>{0, 1, 1, 3}, 2),
                     "CmaEs::tell_ranked: the order is not a permutation of 0..3 (candidate 1)");
  EXPECT_INPUT_ERROR(cma.tell_ranked(std::vector<int>{0, 1, 2, 3}, 5),
                     "CmaEs::tell_ranked parents = 5 is out of range: must be in [0, 4]");
}

}  // namespace
}  // namespace qdmeta
