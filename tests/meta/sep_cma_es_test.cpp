// Tests of the separable CMA-ES (src/qdmeta/meta/sep_cma_es.{hpp,cpp}): its sampling and update
// against a reference written here from Ros & Hansen (2008) with the tutorial's rates, given the
// same samples; known optima at n = 100; fewer evaluations than the full CMA-ES on the separable
// ellipsoid; determinism, checkpoints, tell_ranked and the refusals.
#include "qdmeta/meta/sep_cma_es.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numeric>
#include <vector>

#include "es_objectives.hpp"
#include "expect_input_error.hpp"
#include "qdmeta/core/binary_io.hpp"

namespace qdmeta {
namespace {

using test::evaluate;
using test::sphere;

CmaEsParams sep_unbounded(int n, int lambda, double x0, double sigma0) {
  CmaEsParams p;
  p.dimension = n;
  p.population_size = lambda;
  p.initial_mean = x0;
  p.initial_sigma = sigma0;
  p.bounds = CmaBoundsHandling::kNone;
  return p;
}

double separable_ellipsoid(const Eigen::VectorXd& x) {  // separable, condition number 1e6
  const double n = static_cast<double>(x.size());
  double f = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) f += std::pow(1e6, static_cast<double>(i) / (n - 1.0)) * x(i) * x(i);
  return f;
}

// The reference: sep-CMA-ES's state and one generation's update, written from the equations
// (Ros & Hansen 2008, Hansen's tutorial's Table 1 for the rates) with Eigen's array algebra.
struct Reference {
  Eigen::ArrayXd m, C, ps, pc;
  double sigma;
  int g = 0;

  void update(const Eigen::MatrixXd& x, const Eigen::VectorXd& f) {
    const auto n = static_cast<double>(m.size());
    const auto lambda = static_cast<int>(x.cols());
    const int mu = lambda / 2;
    Eigen::ArrayXd w(mu);
    for (int i = 0; i < mu; ++i) w(i) = std::log((lambda + 1.0) / 2.0) - std::log(i + 1.0);
    w /= w.sum();
    const double mueff = 1.0 / w.square().sum();
    const double cs = (mueff + 2.0) / (n + mueff + 5.0);
    const double ds = 1.0 + 2.0 * std::max(0.0, std::sqrt((mueff - 1.0) / (n + 1.0)) - 1.0) + cs;
    const double cc = (4.0 + mueff / n) / (n + 4.0 + 2.0 * mueff / n);
    const double c1 = 2.0 / ((n + 1.3) * (n + 1.3) + mueff) * (n + 2.0) / 3.0;
    const double cmu = std::min(1.0 - c1, 2.0 * (mueff - 2.0 + 1.0 / mueff) / ((n + 2.0) * (n + 2.0) + mueff) *
                                              (n + 2.0) / 3.0);
    const double chin = std::sqrt(n) * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n));
    std::vector<int> rank(static_cast<std::size_t>(lambda));
    std::iota(rank.begin(), rank.end(), 0);
    std::stable_sort(rank.begin(), rank.end(), [&f](int a, int b) { return f(a) < f(b); });
    Eigen::ArrayXd yw = Eigen::ArrayXd::Zero(m.size());
    Eigen::ArrayXd ymu = Eigen::ArrayXd::Zero(m.size());
    for (int i = 0; i < mu; ++i) {
      const Eigen::ArrayXd y = (x.col(rank[static_cast<std::size_t>(i)]).array() - m) / sigma;
      yw += w(i) * y;
      ymu += w(i) * y.square();
    }
    g += 1;
    m += sigma * yw;
    ps = (1.0 - cs) * ps + std::sqrt(cs * (2.0 - cs) * mueff) * yw / C.sqrt();
    const double norm = std::sqrt(ps.square().sum());
    const bool hs = norm / std::sqrt(1.0 - std::pow(1.0 - cs, 2.0 * g)) < (1.4 + 2.0 / (n + 1.0)) * chin;
    pc = (1.0 - cc) * pc + (hs ? std::sqrt(cc * (2.0 - cc) * mueff) : 0.0) * yw;
    C = (1.0 - c1 - cmu + (hs ? 0.0 : c1 * cc * (2.0 - cc))) * C + c1 * pc.square() + cmu * ymu;
    sigma *= std::exp(cs / ds * (norm / chin - 1.0));
  }
};

double max_relative_difference(const Eigen::ArrayXd& a, const Eigen::VectorXd& b) {
  return ((a - b.array()).abs() / a.abs().max(1e-300)).maxCoeff();
}

TEST(SepCmaEsReference, SamplesAndUpdatesAsTheEquationsGivenTheSameNormals) {
  const int n = 7, lambda = 10;
  SepCmaEs sep(sep_unbounded(n, lambda, 0.3, 0.5));
  Reference ref{Eigen::ArrayXd::Constant(n, 0.3), Eigen::ArrayXd::Ones(n), Eigen::ArrayXd::Zero(n),
                Eigen::ArrayXd::Zero(n), 0.5};
  // A fixed, seed-free stream of "normals"; the ellipsoid gives C an unequal diagonal.
  int draw = 0;
  const std::function<double()> normals = [&draw] { return std::sin(1.7 * ++draw) * 1.3; };
  for (int generation = 0; generation < 30; ++generation) {
    const int first = draw;
    const Eigen::MatrixXd x = sep.ask(normals);
    for (int k = 0; k < lambda; ++k) {
      for (int i = 0; i < n; ++i) {
        const double z = std::sin(1.7 * (first + k * n + i + 1)) * 1.3;
        ASSERT_NEAR(x(i, k), ref.m(i) + ref.sigma * std::sqrt(ref.C(i)) * z, 1e-12 * (1.0 + std::abs(x(i, k))));
      }
    }
    const Eigen::VectorXd f = evaluate(x, separable_ellipsoid);
    sep.tell(f, CmaObjective::kMinimise);
    ref.update(x, f);
    const SepCmaEsState& s = sep.state();
    EXPECT_LT(max_relative_difference(ref.m, s.mean), 1e-11) << generation;
    EXPECT_LT(max_relative_difference(ref.C, s.C), 1e-11) << generation;
    EXPECT_LT(max_relative_difference(ref.ps, s.p_sigma), 1e-11) << generation;
    EXPECT_LT(max_relative_difference(ref.pc, s.p_c), 1e-11) << generation;
    EXPECT_NEAR(s.sigma, ref.sigma, 1e-11 * ref.sigma) << generation;
  }
  // The run moved C off the identity, unequally, and shrank the step.
  EXPECT_GT(sep.state().C.maxCoeff() / sep.state().C.minCoeff(), 2.0);
  EXPECT_LT(sep.state().sigma, 0.5);
}

TEST(SepCmaEsStrategy, RatesAreTheFullEsScaledByNPlus2Over3) {
  for (const int n : {1, 2, 10, 100, 1000}) {
    const CmaEsParams p = sep_unbounded(n, 12, 0.0, 1.0);
    const CmaEsStrategy full = CmaEs(p).strategy();
    const CmaEsStrategy sep = SepCmaEs(p).strategy();
    const double factor = (n + 2.0) / 3.0;
    EXPECT_DOUBLE_EQ(sep.c1, full.c1 * factor) << n;
    EXPECT_DOUBLE_EQ(sep.c_mu, std::min(1.0 - sep.c1, full.c_mu * factor)) << n;
    EXPECT_EQ(sep.c_sigma, full.c_sigma);
    EXPECT_EQ(sep.d_sigma, full.d_sigma);
    EXPECT_EQ(sep.c_c, full.c_c);
    EXPECT_TRUE(sep.weights == full.weights);
    EXPECT_LT(sep.c1 + sep.c_mu, 1.0 + 1e-15);
  }
}

// Evaluations until the best of a generation is below 1e-8 (max_evaluations if never).
template <class Es>
std::int64_t es_evaluations_to_target(const CmaEsParams& p, const std::function<double(const Eigen::VectorXd&)>& f,
                                   std::uint64_t seed, std::int64_t max_evaluations) {
  Es es(p);
  Rng rng(seed);
  while (es.state().evaluations < max_evaluations) {
    const Eigen::VectorXd values = evaluate(es.ask(rng), f);
    es.tell(values, CmaObjective::kMinimise);
    if (values.minCoeff() < 1e-8) return es.state().evaluations;
  }
  return max_evaluations;
}

TEST(SepCmaEsConvergence, SphereAndEllipsoidAt100DimensionsReachTheOptimum) {
  const CmaEsParams p = sep_unbounded(100, 17, 1.0, 1.0);  // 4 + floor(3 ln 100) = 17
  for (const std::uint64_t seed : {1, 2, 3}) {
    EXPECT_LT(es_evaluations_to_target<SepCmaEs>(p, sphere, seed, 40'000), 40'000) << seed;
    EXPECT_LT(es_evaluations_to_target<SepCmaEs>(p, separable_ellipsoid, seed, 150'000), 150'000) << seed;
  }
}

TEST(SepCmaEsConvergence, SeparableEllipsoidTakesFewerEvaluationsThanTheFullEs) {
  // The full ES learns n (n + 1) / 2 covariances at rates ~ 1 / n^2, the separable one n at
  // ~ 1 / n: on the separable ellipsoid the full ES needs more than 3x the evaluations (n = 30
  // keeps the full runs quick; docs/cma_es.md quotes the counts this prints).
  const CmaEsParams p = sep_unbounded(30, 14, 1.0, 1.0);  // 4 + floor(3 ln 30) = 14
  for (const std::uint64_t seed : {1, 2}) {
    const std::int64_t sep = es_evaluations_to_target<SepCmaEs>(p, separable_ellipsoid, seed, 40'000);
    const std::int64_t full = es_evaluations_to_target<CmaEs>(p, separable_ellipsoid, seed, 200'000);
    std::printf("ellipsoid n = 30, lambda = 14, seed %d: separable %lld, full %lld evaluations\n",
                static_cast<int>(seed), static_cast<long long>(sep), static_cast<long long>(full));
    ASSERT_LT(full, 200'000);
    EXPECT_GT(full, 3 * sep) << seed;
  }
}

TEST(SepCmaEsDeterminism, SameSeedSameBitsAndCheckpointsContinueToTheSameBits) {
  const CmaEsParams p = sep_unbounded(20, 8, 0.2, 0.3);
  SepCmaEs a(p), b(p);
  Rng ra(5), rb(5);
  for (int g = 0; g < 10; ++g) {
    a.tell(evaluate(a.ask(ra), separable_ellipsoid), CmaObjective::kMinimise);
    b.tell(evaluate(b.ask(rb), separable_ellipsoid), CmaObjective::kMinimise);
  }
  EXPECT_TRUE(a.state() == b.state());
  a.ask(ra);  // a pending ask is part of the checkpoint
  BinaryWriter out;
  a.save(out);
  SepCmaEs resumed(p);
  BinaryReader in(out.bytes(), "test");
  resumed.load(in);
  in.finish();
  EXPECT_TRUE(resumed.state() == a.state());
  Rng rr = ra;
  for (int g = 0; g < 10; ++g) {
    a.tell(evaluate(a.state().samples, separable_ellipsoid), CmaObjective::kMinimise);
    resumed.tell(evaluate(resumed.state().samples, separable_ellipsoid), CmaObjective::kMinimise);
    a.ask(ra);
    resumed.ask(rr);
  }
  EXPECT_TRUE(resumed.state() == a.state());
  // A full CMA-ES checkpoint is not a separable one.
  BinaryWriter full;
  CmaEs(p).save(full);
  BinaryReader wrong(full.bytes(), "test");
  EXPECT_THROW(resumed.load(wrong), InputError);
}

TEST(SepCmaEsRanked, HalfTheBatchAsParentsIsTellBitForBitAndZeroOnlyClosesTheAsk) {
  const CmaEsParams p = sep_unbounded(6, 10, 0.4, 0.3);  // even: ln((lambda + 1) / 2) = ln(mu + 1/2)
  SepCmaEs told(p), ranked(p), closed(p);
  Rng r1(3), r2(3), r3(3);
  for (int g = 0; g < 8; ++g) {
    const Eigen::VectorXd f = evaluate(told.ask(r1), sphere);
    ranked.ask(r2);
    told.tell(f, CmaObjective::kMinimise);
    std::vector<int> order(10);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&f](int a, int b) { return f(a) < f(b); });
    ranked.tell_ranked(order, 5);
  }
  EXPECT_TRUE(told.state() == ranked.state());
  const SepCmaEsState before = closed.state();
  closed.ask(r3);
  closed.tell_ranked(std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, 0);
  EXPECT_TRUE(closed.state().mean == before.mean);
  EXPECT_TRUE(closed.state().C == before.C);
  EXPECT_EQ(closed.state().generation, 1);
}

TEST(SepCmaEsBounds, ClampKeepsEveryCandidateInside) {
  CmaEsParams p = sep_unbounded(50, 10, 0.5, 2.0);
  p.bounds = CmaBoundsHandling::kClamp;
  p.lower_bound = 0.0;
  p.upper_bound = 1.0;
  SepCmaEs sep(p);
  Rng rng(1);
  const Eigen::MatrixXd& x = sep.ask(rng);
  EXPECT_GE(x.minCoeff(), 0.0);
  EXPECT_LE(x.maxCoeff(), 1.0);
  EXPECT_GT((x.array() == 0.0).count(), 0);  // sigma 2 from 0.5: many clamped
}

TEST(SepCmaEsProtocol, RefusesMisuseAndTheFullEsOnlySettings) {
  CmaEsParams p = sep_unbounded(3, 4, 0.0, 1.0);
  SepCmaEs sep(p);
  EXPECT_INPUT_ERROR(sep.tell(Eigen::VectorXd::Zero(4), CmaObjective::kMinimise),
                     "SepCmaEs::tell: called without a pending ask; call ask() first");
  Rng rng(1);
  sep.ask(rng);
  EXPECT_INPUT_ERROR(sep.ask(rng), "SepCmaEs::ask: called twice without tell; tell the fitness of the 4 pending "
                                   "candidates first");
  EXPECT_INPUT_ERROR(sep.tell(Eigen::VectorXd::Zero(3), CmaObjective::kMinimise),
                     "SepCmaEs::tell: expected 4 fitness values, got 3");
  EXPECT_INPUT_ERROR(sep.tell_ranked(std::vector<int>{0, 1, 1, 2}, 2),
                     "SepCmaEs::tell_ranked: the order is not a permutation of 0..3 (candidate 1)");
  p.rank_one = CmaRankOne::kPyribs;
  EXPECT_INPUT_ERROR(SepCmaEs{p}, "CmaEsParams.rank_one = pyribs is not available in the separable CMA-ES: only "
                                  "tutorial");
  p = sep_unbounded(3, 1, 0.0, 1.0);
  p.small_population = CmaSmallPopulation::kAuthors;
  EXPECT_INPUT_ERROR(SepCmaEs{p},
                     "CmaEsParams.small_population = authors is not available in the separable CMA-ES: use one-one");
  SepCmaEsState bad = SepCmaEs(sep_unbounded(3, 4, 0.0, 1.0)).state();
  bad.C(1) = 0.0;
  EXPECT_INPUT_ERROR(sep.set_state(bad), "SepCmaEs::set_state: C has entries <= 0 or not finite");
}

}  // namespace
}  // namespace qdmeta
