// bench/peers/cma_domains.hpp against values worked out by hand (the same values as
// tests/tools/test_cma_domains.py checks in bench/peers/common.py, so both peers evaluate alike).
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "cma_domains.hpp"

namespace qdmeta::peers {
namespace {

constexpr Index kGenes = 100;

struct Evaluation {
  double objective = 0.0, m0 = 0.0, m1 = 0.0;
};

template <class F>
Evaluation evaluate(F f, const std::vector<Real>& x) {
  Evaluation e;
  double m[2];
  f(x.data(), static_cast<Index>(x.size()), e.objective, m);
  e.m0 = m[0];
  e.m1 = m[1];
  return e;
}

// The genes in float, as the scheduler hands them over: 1e-4 covers their rounding on a 0..100
// scale, far below any error in the formulas (a wrong shift, fold or half moves them by > 0.1).
constexpr double kTolerance = 1e-4;

TEST(CmaDomains, SphereAtItsOptimumTheOriginAndTheFold) {
  const Evaluation optimum = evaluate(lin_proj_sphere, std::vector<Real>(kGenes, 2.048f));
  EXPECT_NEAR(optimum.objective, 100.0, kTolerance);
  EXPECT_NEAR(optimum.m0, 102.4, kTolerance);
  EXPECT_NEAR(optimum.m1, 102.4, kTolerance);
  // S / W = (2.048 / 7.168)^2 = 4 / 49.
  const Evaluation origin = evaluate(lin_proj_sphere, std::vector<Real>(kGenes, 0.0f));
  EXPECT_NEAR(origin.objective, 100.0 * 45.0 / 49.0, kTolerance);
  EXPECT_EQ(origin.m0, 0.0);
  EXPECT_EQ(origin.m1, 0.0);
  // -5.12 is inside the box (kept): the worst corner scores 0 and sums to -256.
  const Evaluation corner = evaluate(lin_proj_sphere, std::vector<Real>(kGenes, -5.12f));
  EXPECT_NEAR(corner.objective, 0.0, kTolerance);
  EXPECT_NEAR(corner.m0, -256.0, 1e-3);
  // 10.24 folds to 5.12 / 10.24 = 0.5 in the first half; S / W = (64 / 49 + 1) / 2 = 113 / 98.
  std::vector<Real> mixed(kGenes, -5.12f);
  for (Index j = 0; j < kGenes / 2; ++j) mixed[static_cast<std::size_t>(j)] = 10.24f;
  const Evaluation m = evaluate(lin_proj_sphere, mixed);
  EXPECT_NEAR(m.objective, -1500.0 / 98.0, kTolerance);
  EXPECT_NEAR(m.m0, 25.0, kTolerance);
  EXPECT_NEAR(m.m1, -256.0, 1e-3);
  EXPECT_DOUBLE_EQ(lin_proj_sphere_domain(kGenes).measure_bound, 256.0);
}

TEST(CmaDomains, ArmStraightAlternatingClosedAndFolded) {
  const Evaluation straight = evaluate(arm, std::vector<Real>(kGenes, 0.0f));
  EXPECT_EQ(straight.objective, 100.0);
  EXPECT_EQ(straight.m0, 100.0);
  EXPECT_EQ(straight.m1, 0.0);
  // +0.5, -0.5, ...: headings alternate 0.5 and 0, variance 0.25.
  std::vector<Real> zigzag(kGenes);
  for (Index j = 0; j < kGenes; ++j) zigzag[static_cast<std::size_t>(j)] = j % 2 == 0 ? 0.5f : -0.5f;
  const Evaluation z = evaluate(arm, zigzag);
  EXPECT_NEAR(z.objective, 75.0, kTolerance);
  EXPECT_NEAR(z.m0, 50.0 + 50.0 * std::cos(0.5), kTolerance);
  EXPECT_NEAR(z.m1, 50.0 * std::sin(0.5), kTolerance);
  // Every joint 2 pi / 100: the arm closes a regular polygon and ends at the base.
  const Evaluation closed = evaluate(arm, std::vector<Real>(kGenes, static_cast<Real>(2.0 * std::numbers::pi / kGenes)));
  EXPECT_NEAR(closed.objective, 100.0, kTolerance);
  EXPECT_NEAR(closed.m0, 0.0, 1e-3);
  EXPECT_NEAR(closed.m1, 0.0, 1e-3);
  // The first joint pi, the rest 0: the arm points back; Var = 0.99 pi^2 / 100.
  std::vector<Real> back(kGenes, 0.0f);
  back[0] = static_cast<Real>(std::numbers::pi);
  const Evaluation b = evaluate(arm, back);
  EXPECT_NEAR(b.objective, 100.0 - 0.99 * std::numbers::pi * std::numbers::pi, kTolerance);
  EXPECT_NEAR(b.m0, -100.0, kTolerance);
  EXPECT_NEAR(b.m1, 0.0, 1e-3);
  EXPECT_DOUBLE_EQ(arm_domain(kGenes).measure_bound, 100.0);
}

TEST(CmaDomains, EvaluateRowsFillsEveryRow) {
  RowMatrix x(2, kGenes);
  x.row(0).setConstant(2.048f);
  x.row(1).setZero();
  std::vector<Real> objectives;
  RowMatrix measures;
  evaluate_rows(x, lin_proj_sphere, objectives, measures);
  ASSERT_EQ(objectives.size(), 2u);
  EXPECT_NEAR(objectives[0], 100.0, kTolerance);
  EXPECT_NEAR(objectives[1], 100.0 * 45.0 / 49.0, kTolerance);
  EXPECT_NEAR(measures(0, 1), 102.4, kTolerance);
  EXPECT_EQ(measures(1, 0), 0.0f);
}

}  // namespace
}  // namespace qdmeta::peers
