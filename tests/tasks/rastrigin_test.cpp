// Tests of src/qdmeta/tasks/rastrigin/rastrigin.{hpp,cpp} and rastrigin_task.{hpp,cpp}:
// known answers at hand-computed points (after pagmo2's tests/rastrigin.cpp), the variants of
// docs/specification.md (Rastrigin), the vectorised float path against the double reference, and the samplers.
//
// Hand computations used below (x = -5.12 + 10.24 g; t(x) = x^2 - 10 cos(2 pi x) + 10, so that
// f = -sum_i t(x_i)):
//   g = 0.5   -> x = 0:      t = 0 - 10 cos 0 + 10 = 0.
//   g = 0     -> x = -5.12:  cos(2 pi 5.12) = cos(10.24 pi) = cos(0.24 pi) = cos(43.2 deg)
//                            = 0.7289686274214115 (five whole turns dropped);
//                            t = 26.2144 - 7.289686274214115 + 10 = 28.924713725785885.
//                            20-D: f = -20 t = -578.4942745157177.
//   g = 1     -> x = +5.12:  same t (the function is even).
//   g = 0.75  -> x = 2.56:   cos(5.12 pi) = cos(1.12 pi) = -cos(0.12 pi) = -cos(21.6 deg)
//                            = -0.9297764858882514; t = 6.5536 + 9.297764858882514 + 10
//                            = 25.851364858882514.
//   g = 0.25  -> x = -2.56:  same t.
//   g = 0.625 -> x = 1.28:   cos(2.56 pi) = cos(0.56 pi) = -sin(0.06 pi) = -sin(10.8 deg)
//                            = -0.18738131458572463; t = 1.6384 + 1.8738131458572463 + 10
//                            = 13.512213145857246.
//   Mixed 20-D point g = (0, 0.75, 0.25, 0.625, 0.5 x 16):
//     f = -(28.924713725785885 + 2 x 25.851364858882514 + 13.512213145857246)
//       = -94.13965658940816.
//   Dimension test, noise term -10 sin(6 pi x):
//     x = 2.56:  sin(15.36 pi) = sin(1.36 pi) = -sin(0.36 pi) = -0.9048270524660195 -> +9.048270524660195
//     x = -5.12: sin(-30.72 pi) = -sin(0.72 pi) = -sin(0.28 pi) = -0.7705132427757892 -> +7.705132427757892
//     x = 0:     sin 0 = 0.
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

using namespace rastrigin;

constexpr double kT0 = 28.924713725785885;     // t at g = 0 or 1
constexpr double kT75 = 25.851364858882514;    // t at g = 0.75 or 0.25
constexpr double kT625 = 13.512213145857246;   // t at g = 0.625

std::vector<Real> filled(std::size_t n, Real g) { return std::vector<Real>(n, g); }

std::vector<Real> random_genotype(Rng& rng, std::size_t n) {
  std::vector<Real> g(n);
  for (Real& x : g) x = static_cast<Real>(rng.uniform());
  return g;
}

TEST(Rastrigin, OptimumIsZeroAtTheCentre) {
  EXPECT_EQ(standard(filled(20, 0.5f)), 0.0);
  EXPECT_EQ(standard(filled(3, 0.5f)), 0.0);
}

TEST(Rastrigin, CornersOf20D) {
  EXPECT_NEAR(standard(filled(20, 0.0f)), -578.4942745157177, 1e-6);
  EXPECT_NEAR(standard(filled(20, 1.0f)), -578.4942745157177, 1e-6);
  EXPECT_NEAR(standard(filled(1, 0.0f)), -kT0, 1e-9);
}

TEST(Rastrigin, MixedPoint) {
  std::vector<Real> g = filled(20, 0.5f);
  g[0] = 0.0f;
  g[1] = 0.75f;
  g[2] = 0.25f;
  g[3] = 0.625f;
  EXPECT_NEAR(standard(g), -94.13965658940816, 1e-9);
  EXPECT_NEAR(standard(g), -(kT0 + 2 * kT75 + kT625), 1e-9);
  // Order does not matter.
  std::reverse(g.begin(), g.end());
  EXPECT_NEAR(standard(g), -94.13965658940816, 1e-9);
}

TEST(Rastrigin, NeverPositive) {
  Rng rng(41);
  for (int i = 0; i < 1000; ++i) ASSERT_LE(standard(random_genotype(rng, 20)), 0.0);
}

TEST(Rastrigin, WithoutDimension) {
  for (int j : {0, 7, 19}) EXPECT_EQ(without_dimension(filled(20, 0.5f), j), 0.0);
  // Dropping the only off-centre gene gives 0; dropping another gives that gene's term.
  std::vector<Real> g = filled(20, 0.5f);
  g[4] = 0.0f;
  EXPECT_NEAR(without_dimension(g, 4), 0.0, 1e-12);
  EXPECT_NEAR(without_dimension(g, 5), -kT0, 1e-9);

  Rng rng(42);
  for (int rep = 0; rep < 20; ++rep) {
    const std::vector<Real> r = random_genotype(rng, 20);
    for (int j = 0; j < 20; ++j) {
      std::vector<Real> reduced = r;
      reduced.erase(reduced.begin() + j);
      ASSERT_NEAR(without_dimension(r, j), standard(reduced), 1e-9) << "j = " << j;
    }
  }
}

TEST(Rastrigin, TranslatedIdentityEqualsStandard) {
  Rng rng(43);
  for (int rep = 0; rep < 100; ++rep) {
    const std::vector<Real> g = random_genotype(rng, 20);
    const auto t = translated(g, 1.0, 0.0);
    ASSERT_TRUE(t.has_value());
    ASSERT_DOUBLE_EQ(*t, standard(g));
  }
  // The range bound itself is in range: |x'| = 5.12 is allowed.
  const auto edge = translated(filled(20, 0.0f), 1.0, 0.0);
  ASSERT_TRUE(edge.has_value());
  EXPECT_NEAR(*edge, -578.4942745157177, 1e-6);
}

TEST(Rastrigin, TranslatedKnownValues) {
  // x' = 0 + 0.5 everywhere: t = 0.25 - 10 cos(pi) + 10 = 20.25, f = -20 x 20.25 = -405.
  const auto shifted = translated(filled(20, 0.5f), 1.0, 0.5);
  ASSERT_TRUE(shifted.has_value());
  EXPECT_NEAR(*shifted, -405.0, 1e-9);
  // Any slope maps x = 0 to 0.
  EXPECT_EQ(translated(filled(20, 0.5f), 1.1, 0.0), 0.0);
  EXPECT_EQ(translated(filled(20, 0.5f), -1.0 / 1.1, 0.0), 0.0);
  // Reversal: a = -1 maps x = 2.56 to -2.56 (same t).
  std::vector<Real> g = filled(20, 0.5f);
  g[0] = 0.75f;
  const auto reversed = translated(g, -1.0, 0.0);
  ASSERT_TRUE(reversed.has_value());
  EXPECT_NEAR(*reversed, -kT75, 1e-9);
}

TEST(Rastrigin, TranslatedOutOfRangeIsNullopt) {
  EXPECT_FALSE(translated(filled(20, 0.0f), 1.1, 0.0).has_value());  // x' = -5.632
  EXPECT_FALSE(translated(filled(20, 1.0f), 1.1, 0.0).has_value());  // x' = +5.632
  EXPECT_FALSE(translated(filled(20, 1.0f), 1.0, 0.01).has_value()); // x' = 5.13
  EXPECT_FALSE(translated(filled(20, 0.0f), -1.0, 0.5).has_value()); // x' = 5.62
  // One gene out of range is enough.
  std::vector<Real> g = filled(20, 0.5f);
  g[13] = 1.0f;
  EXPECT_FALSE(translated(g, 1.1, 0.0).has_value());
  EXPECT_FALSE(translated(g, 1.0, 0.5).has_value());
  EXPECT_TRUE(translated(g, 1.0, -0.5).has_value());
}

TEST(Rastrigin, DimensionTestKnownValues) {
  const std::vector<int> dims = {3, 7};
  // At the centre the noise terms are 10 sin 0 = 0 and the rest is 0.
  EXPECT_NEAR(dimension_test(filled(20, 0.5f), dims), 0.0, 1e-12);
  // g3 = 0.75 (x = 2.56, noise +9.048270524660195), g7 = 0 (x = -5.12, noise +7.705132427757892),
  // g0 = 0.625 (x = 1.28, t - 10 = 3.512213145857246), 17 genes at the centre (each -10):
  // f = -[10 x 18 + (-170 + 3.512213145857246 + 9.048270524660195 + 7.705132427757892)]
  //   = -30.265616098275334.
  std::vector<Real> g = filled(20, 0.5f);
  g[3] = 0.75f;
  g[7] = 0.0f;
  g[0] = 0.625f;
  EXPECT_NEAR(dimension_test(g, dims), -30.265616098275334, 1e-9);
  // The noise replaces the Rastrigin term only in the chosen dimensions.
  EXPECT_NEAR(dimension_test(g, std::vector<int>{1, 2}), standard(g), 1e-9);
  // With no dimensions removed it is the standard function.
  EXPECT_NEAR(dimension_test(g, std::vector<int>{}), standard(g), 1e-9);
}

TEST(Rastrigin, Score) {
  EXPECT_EQ(score(0.0), 2000.0);
  EXPECT_EQ(score(-100.0), 1900.0);
  EXPECT_EQ(score(-2000.0), 0.0);
  EXPECT_EQ(score(-5000.0), 0.0);
  EXPECT_EQ(score(-1999.5), 0.5);
  EXPECT_EQ(score(-3.0, 10.0), 7.0);
  EXPECT_EQ(score(-30.0, 10.0), 0.0);
  EXPECT_EQ(kDefaultScoreM, 2000.0);
}

TEST(Rastrigin, Cos2PiMatchesStdCos) {
  double worst = 0.0;
  double worst_x = 0.0;
  constexpr int kSteps = 240'000;  // step 5e-5 over [-6, 6]
  for (int i = 0; i <= kSteps; ++i) {
    const auto x = static_cast<Real>(-6.0 + 12.0 * i / kSteps);
    const double expected = std::cos(2.0 * std::numbers::pi * static_cast<double>(x));
    const double err = std::abs(static_cast<double>(cos_2pi(x)) - expected);
    if (err > worst) {
      worst = err;
      worst_x = x;
    }
  }
  EXPECT_LT(worst, 2e-7) << "at x = " << worst_x;
  // Exact-ish landmarks: whole, half and quarter turns.
  for (Real x : {-5.0f, -1.0f, 0.0f, 1.0f, 3.0f}) EXPECT_NEAR(cos_2pi(x), 1.0f, 1e-7f) << x;
  for (Real x : {-4.5f, 0.5f, 2.5f}) EXPECT_NEAR(cos_2pi(x), -1.0f, 1e-7f) << x;
  for (Real x : {-0.25f, 0.25f, 0.75f, 5.25f}) EXPECT_NEAR(cos_2pi(x), 0.0f, 2e-7f) << x;
}

TEST(Rastrigin, EvaluateBatchAgreesWithStandard) {
  for (Index n : {Index{20}, Index{7}, Index{1}}) {  // 7 and 1 exercise the tail of the 4-way sums
    constexpr Index kCount = 10'000;
    Rng rng(44);
    RowMatrix g(kCount, n);
    for (Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<Real>(rng.uniform());
    std::vector<Real> fitness(kCount);
    std::vector<Real> scratch;
    evaluate_batch(g.data(), kCount, n, fitness.data(), scratch);
    for (Index r = 0; r < kCount; ++r) {
      const double ref = standard(std::span<const Real>(g.row(r).data(), static_cast<std::size_t>(n)));
      ASSERT_NEAR(fitness[static_cast<std::size_t>(r)], ref, 1e-3 + 1e-5 * std::abs(ref)) << "n " << n << " row " << r;
    }
  }
}

TEST(Rastrigin, EvaluateBatchKnownPoints) {
  RowMatrix g(3, 20);
  g.row(0).setConstant(0.5f);
  g.row(1).setConstant(0.0f);
  g.row(2).setConstant(0.5f);
  g(2, 0) = 0.0f;
  g(2, 1) = 0.75f;
  g(2, 2) = 0.25f;
  g(2, 3) = 0.625f;
  std::vector<Real> fitness(3);
  std::vector<Real> scratch;
  evaluate_batch(g.data(), 3, 20, fitness.data(), scratch);
  EXPECT_NEAR(fitness[0], 0.0, 1e-4);
  EXPECT_NEAR(fitness[1], -578.4942745157177, 1e-3);
  EXPECT_NEAR(fitness[2], -94.13965658940816, 1e-3);
}

TEST(RastriginTask, WrapsAsATask) {
  const Task task{RastriginTask{}};
  EXPECT_EQ(task.name(), "rastrigin");
  EXPECT_EQ(task.genotype_size(), 20);
  EXPECT_EQ(task.base_feature_size(), 20);
  EXPECT_TRUE(task.shareable());
  EXPECT_EQ(task.qd_offset(), -2000.0);

  RastriginParams p;
  p.dimensions = 5;
  p.score_m = 100.0;
  const Task small{RastriginTask{p}};
  EXPECT_EQ(small.genotype_size(), 5);
  EXPECT_EQ(small.qd_offset(), -100.0);
}

TEST(RastriginTask, BaseFeaturesAreTheGenotypeAndAllValid) {
  const Task task{RastriginTask{}};
  constexpr Index kCount = 64;
  Rng rng(45);
  RowMatrix g(kCount, 20);
  for (Index k = 0; k < g.size(); ++k) g.data()[k] = static_cast<Real>(rng.uniform());
  g.row(0).setConstant(0.0f);
  g.row(1).setConstant(1.0f);
  EvaluationBatch out;
  out.resize(kCount, 20);
  task.evaluate({g.data(), kCount, 20}, out.view());
  EXPECT_EQ(out.base_features, g);
  EXPECT_EQ(out.valid, std::vector<std::uint8_t>(kCount, 1));
  for (Index r = 0; r < kCount; ++r) {
    const double ref = standard(std::span<const Real>(g.row(r).data(), 20));
    EXPECT_NEAR(out.fitness[r], ref, 1e-3 + 1e-5 * std::abs(ref));
  }
}

TEST(RastriginTask, ParamsValidate) {
  EXPECT_NO_THROW(RastriginParams{}.validate());
  RastriginParams p;
  p.dimensions = 0;
  try {
    p.validate();
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("task.dimensions = 0"), std::string::npos) << e.what();
  }
  p = RastriginParams{};
  p.score_m = 0.0;
  try {
    p.validate();
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("task.score_m = 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(RastriginTask{p}, InputError);
}

TEST(Rastrigin, TranslationTestGrid) {
  const std::vector<LinearTransform> grid = translation_test_grid();
  ASSERT_EQ(grid.size(), 120u);
  std::set<std::pair<double, double>> unique;
  std::set<double> slopes, intercepts;
  for (const auto& t : grid) {
    unique.insert({t.a, t.b});
    slopes.insert(t.a);
    intercepts.insert(t.b);
  }
  EXPECT_EQ(unique.size(), 120u);

  std::set<double> expected_slopes;
  for (double ap : {0.01, 0.25, 0.5})
    for (double s : {1.0, -1.0}) {
      expected_slopes.insert(s * (1.0 + ap));
      expected_slopes.insert(s / (1.0 + ap));
    }
  ASSERT_EQ(expected_slopes.size(), 12u);
  EXPECT_EQ(slopes, expected_slopes);
  const std::set<double> expected_intercepts = {-1.0, -0.75, -0.5, -0.25, -0.01, 0.01, 0.25, 0.5, 0.75, 1.0};
  EXPECT_EQ(intercepts, expected_intercepts);
  // 12 x 10 distinct pairs over 12 slopes and 10 intercepts: the full product.
  for (double a : expected_slopes)
    for (double b : expected_intercepts) EXPECT_TRUE(unique.contains({a, b})) << a << ", " << b;
}

TEST(Rastrigin, SampleMetaTransformsTwoPerRange) {
  Rng rng(46);
  const std::vector<LinearTransform> ts = sample_meta_transforms(rng);
  ASSERT_EQ(ts.size(), 16u);
  // Range = (sign of a, expand or shrink, sign of b).
  std::map<std::tuple<bool, bool, bool>, int> per_range;
  for (const auto& t : ts) {
    const double mag = std::abs(t.a);
    const bool expand = mag > 1.0;
    if (expand) {
      EXPECT_GE(mag, 1.0);
      EXPECT_LE(mag, 1.1);
    } else {
      EXPECT_GE(mag, 1.0 / 1.1);
      EXPECT_LE(mag, 1.0);
    }
    EXPECT_GE(t.b, -0.5);
    EXPECT_LE(t.b, 0.5);
    ++per_range[{t.a > 0, expand, t.b > 0}];
  }
  EXPECT_EQ(per_range.size(), 8u);
  for (const auto& [range, n] : per_range) EXPECT_EQ(n, 2);

  Rng r3(46);
  EXPECT_EQ(sample_meta_transforms(r3, 3).size(), 24u);
  Rng same(46);
  EXPECT_EQ(sample_meta_transforms(same), ts);
  Rng different(47);
  EXPECT_NE(sample_meta_transforms(different), ts);
}

TEST(Rastrigin, SampleMetaTransformsCoverTheirRanges) {
  // Over many draws each range's slopes and intercepts spread over most of the interval.
  Rng rng(48);
  double min_expand = 2, max_expand = 0, min_shrink = 2, max_shrink = 0, min_b = 1, max_b = -1;
  for (int rep = 0; rep < 200; ++rep)
    for (const auto& t : sample_meta_transforms(rng)) {
      const double mag = std::abs(t.a);
      if (mag > 1.0) {
        min_expand = std::min(min_expand, mag);
        max_expand = std::max(max_expand, mag);
      } else {
        min_shrink = std::min(min_shrink, mag);
        max_shrink = std::max(max_shrink, mag);
      }
      min_b = std::min(min_b, t.b);
      max_b = std::max(max_b, t.b);
    }
  EXPECT_LT(min_expand, 1.005);
  EXPECT_GT(max_expand, 1.095);
  EXPECT_LT(min_shrink, 1.0 / 1.095);
  EXPECT_GT(max_shrink, 1.0 / 1.005);
  EXPECT_LT(min_b, -0.49);
  EXPECT_GT(max_b, 0.49);
}

TEST(Rastrigin, SampleDimensionPairs) {
  Rng rng(49);
  const auto pairs = sample_dimension_pairs(rng, 20, 120);
  ASSERT_EQ(pairs.size(), 120u);
  std::set<std::array<int, 2>> unique(pairs.begin(), pairs.end());
  EXPECT_EQ(unique.size(), 120u);
  for (const auto& p : pairs) {
    EXPECT_GE(p[0], 0);
    EXPECT_LT(p[0], p[1]);
    EXPECT_LT(p[1], 20);
  }
  // All C(20, 2) = 190 pairs can be drawn, not one more.
  EXPECT_EQ(sample_dimension_pairs(rng, 20, 190).size(), 190u);
  EXPECT_TRUE(sample_dimension_pairs(rng, 20, 0).empty());
  try {
    sample_dimension_pairs(rng, 20, 191);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("191"), std::string::npos) << msg;
    EXPECT_NE(msg.find("190"), std::string::npos) << msg;
  }
  EXPECT_THROW(sample_dimension_pairs(rng, 20, -1), InputError);
  EXPECT_THROW(sample_dimension_pairs(rng, 1, 1), InputError);
}

TEST(Rastrigin, SampleDimensionsDistinct) {
  Rng rng(50);
  for (int rep = 0; rep < 50; ++rep) {
    const auto dims = sample_dimensions(rng, 20, 10);
    ASSERT_EQ(dims.size(), 10u);
    const std::set<int> unique(dims.begin(), dims.end());
    ASSERT_EQ(unique.size(), 10u);
    for (int d : dims) {
      ASSERT_GE(d, 0);
      ASSERT_LT(d, 20);
    }
  }
  const auto all = sample_dimensions(rng, 20, 20);
  EXPECT_EQ(std::set<int>(all.begin(), all.end()).size(), 20u);
  EXPECT_THROW(sample_dimensions(rng, 20, 21), InputError);
  EXPECT_THROW(sample_dimensions(rng, 20, -1), InputError);
}

TEST(Rastrigin, SampleDimensionsIsUniform) {
  // Each of 20 dimensions is drawn in 10 of 20 slots: frequency 1/2 per draw of 10.
  Rng rng(51);
  std::vector<int> counts(20, 0);
  constexpr int kReps = 4000;
  for (int rep = 0; rep < kReps; ++rep)
    for (int d : sample_dimensions(rng, 20, 10)) ++counts[static_cast<std::size_t>(d)];
  for (int c : counts) EXPECT_NEAR(c, kReps / 2, 6 * std::sqrt(kReps * 0.25));
}

}  // namespace
}  // namespace qdmeta
