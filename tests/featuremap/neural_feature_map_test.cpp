#include "expect_input_error.hpp"
#include "qdmeta/featuremap/neural_feature_map.hpp"
#include "qdmeta/featuremap/network_kernel.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

NeuralFeatureMapShape shape_of(Index inputs, Index hidden, Index outputs) {
  NeuralFeatureMapShape s;
  s.inputs = inputs;
  s.hidden = hidden;
  s.outputs = outputs;
  return s;
}

std::vector<double> uniform_weights(Index k, double lo, double hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> w(static_cast<std::size_t>(k));
  for (double& x : w) x = u(rng);
  return w;
}

RowMatrix uniform_rows(Index rows, Index cols, float lo, float hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  RowMatrix m(rows, cols);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = u(rng);
  return m;
}

// The network of docs/specification.md (QD-Meta), written out row by row in double precision.
std::vector<double> reference(const NeuralFeatureMapShape& s, const std::vector<double>& w, const Real* b) {
  const auto nb = static_cast<std::size_t>(s.inputs);
  const auto nh = static_cast<std::size_t>(s.hidden);
  const auto nt = static_cast<std::size_t>(s.outputs);
  const double b1 = w[nh * nb];
  const double b2 = w[nh * nb + 1 + nt * nh];
  const double c1 = s.alpha / static_cast<double>(nb + 1);
  const double c2 = s.alpha / static_cast<double>(nh + 1);
  std::vector<double> h(nh);
  for (std::size_t j = 0; j < nh; ++j) {
    double a = b1;
    for (std::size_t k = 0; k < nb; ++k) a += w[j * nb + k] * static_cast<double>(b[k]);
    h[j] = 1.0 / (1.0 + std::exp(-c1 * a));
  }
  std::vector<double> out(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    double a = b2;
    for (std::size_t j = 0; j < nh; ++j) a += w[nh * nb + 1 + t * nh + j] * h[j];
    out[t] = 1.0 / (1.0 + std::exp(-c2 * a));
  }
  return out;
}

TEST(FastExp, MatchesStdExpOverTheWholeRange) {
  double worst = 0.0;
  float worst_x = 0;
  for (int i = 0; i <= 2'000'000; ++i) {
    const float x = -87.3f + (88.3f + 87.3f) * static_cast<float>(i) / 2'000'000.0f;
    const double expected = std::exp(static_cast<double>(x));
    const double rel = std::abs(static_cast<double>(fast_exp(x)) - expected) / expected;
    if (rel > worst) {
      worst = rel;
      worst_x = x;
    }
  }
  EXPECT_LT(worst, 2e-7) << "at x = " << worst_x;
}

TEST(FastExp, ExactAtZeroAndClampedOutsideTheRange) {
  EXPECT_EQ(fast_exp(0.0f), 1.0f);
  EXPECT_TRUE(std::isfinite(fast_exp(1000.0f)));
  EXPECT_EQ(fast_exp(1000.0f), fast_exp(88.3f));
  EXPECT_GE(fast_exp(-1000.0f), std::numeric_limits<float>::min());
  EXPECT_EQ(fast_exp(-1000.0f), fast_exp(-87.3f));
  EXPECT_EQ(fast_exp(-std::numeric_limits<float>::infinity()), fast_exp(-87.3f));
}

TEST(ScaledSigmoid, KnownValues) {
  EXPECT_EQ(scaled_sigmoid(0.0f, 10.0f), 0.5f);
  EXPECT_NEAR(scaled_sigmoid(0.1f, 10.0f), 1.0 / (1.0 + std::exp(-1.0)), 1e-7);
  EXPECT_NEAR(scaled_sigmoid(-0.3f, 2.5f), 1.0 / (1.0 + std::exp(0.75)), 1e-7);
  EXPECT_EQ(scaled_sigmoid(1e6f, 30.0f), 1.0f);
  EXPECT_GE(scaled_sigmoid(-1e6f, 30.0f), 0.0f);
  EXPECT_LT(scaled_sigmoid(-1e6f, 30.0f), 1e-30f);
}

TEST(FastExp2, MatchesStdExp2OverTheWholeRangeAndIsExactAtTheIntegers) {
  double worst = 0.0;
  float worst_t = 0;
  for (int i = 0; i <= 2'000'000; ++i) {
    const float t = -125.0f + 250.0f * static_cast<float>(i) / 2'000'000.0f;
    const double expected = std::exp2(static_cast<double>(t));
    const double rel = std::abs(static_cast<double>(fast_exp2(t)) - expected) / expected;
    if (rel > worst) {
      worst = rel;
      worst_t = t;
    }
  }
  EXPECT_LT(worst, 7e-7) << "at t = " << worst_t;
  for (int k = -125; k <= 125; ++k) EXPECT_EQ(fast_exp2(static_cast<float>(k)), std::ldexp(1.0f, k)) << k;
  EXPECT_EQ(fast_exp2(1000.0f), fast_exp2(125.0f));
  EXPECT_EQ(fast_exp2(-std::numeric_limits<float>::infinity()), fast_exp2(-125.0f));
  EXPECT_GE(fast_exp2(-1000.0f), std::numeric_limits<float>::min());  // no subnormal
}

// base2_sigmoid(z) = 1 / (1 + 2^z): S_N(x) once z = -alpha log2(e) x / (N + 1).
TEST(Base2Sigmoid, KnownValuesAndTheBaseEForm) {
  EXPECT_EQ(base2_sigmoid(0.0f), 0.5f);
  EXPECT_NEAR(base2_sigmoid(1.0f), 1.0 / 3.0, 3e-7);
  EXPECT_NEAR(base2_sigmoid(-3.0f), 8.0 / 9.0, 3e-7);
  EXPECT_EQ(base2_sigmoid(-1e6f), 1.0f);
  EXPECT_GT(base2_sigmoid(1e6f), 0.0f);
  EXPECT_LT(base2_sigmoid(1e6f), 1e-37f);
  // Against the double-precision sigmoid at alpha = 30, N = 20, over x in [-3, 3].
  const double c = 30.0 / 21.0;
  double worst = 0.0;
  for (int i = 0; i <= 60'000; ++i) {
    const double x = -3.0 + 6.0 * i / 60'000.0;
    const auto z = static_cast<float>(-c * 1.4426950408889634 * x);
    worst = std::max(worst, std::abs(static_cast<double>(base2_sigmoid(z)) - 1.0 / (1.0 + std::exp(-c * x))));
  }
  EXPECT_LT(worst, 2e-7);
}

TEST(NeuralFeatureMapShape, WeightCountsOfThePaper) {
  EXPECT_EQ(shape_of(20, 10, 2).weight_count(), 222);  // Rastrigin
  EXPECT_EQ(shape_of(50, 10, 4).weight_count(), 542);  // RHex trajectory
  EXPECT_EQ(shape_of(15, 10, 4).weight_count(), 192);  // RHex feature sets
}

TEST(NeuralFeatureMapShape, DefaultsAndValidation) {
  const NeuralFeatureMapShape defaults;
  EXPECT_EQ(defaults.hidden, 10);
  EXPECT_EQ(defaults.alpha, 30.0);
  EXPECT_NO_THROW(shape_of(20, 10, 2).validate());
  EXPECT_INPUT_ERROR(shape_of(0, 10, 2).validate(),
                     "feature-map inputs (base features) = 0 is out of range: must be at least 1");
  EXPECT_INPUT_ERROR(shape_of(20, 0, 2).validate(), "feature_map.hidden = 0 is out of range: must be at least 1");
  EXPECT_INPUT_ERROR(shape_of(20, 10, 0).validate(),
                     "feature-map outputs (target features) = 0 is out of range: must be at least 1");
  NeuralFeatureMapShape s = shape_of(20, 10, 2);
  s.alpha = 0.0;
  EXPECT_INPUT_ERROR(s.validate(), "feature_map.alpha = 0 is out of range: must be finite and above 0");
}

TEST(NeuralFeatureMap, WrongWeightCountThrowsNamingBothSizes) {
  const std::vector<double> w(221, 0.0);
  EXPECT_INPUT_ERROR(NeuralFeatureMap(shape_of(20, 10, 2), w),
                     "neural feature-map: got 221 weights, but 20 inputs, 10 hidden units and 2 outputs need "
                     "K = 10*20 + 1 + 2*10 + 1 = 222");
  const std::vector<double> more(543, 0.0);
  EXPECT_THROW(NeuralFeatureMap(shape_of(50, 10, 4), more), InputError);
  EXPECT_NO_THROW(NeuralFeatureMap(shape_of(15, 10, 4), std::vector<double>(192, 0.0)));
}

TEST(NeuralFeatureMap, NonFiniteWeightThrows) {
  std::vector<double> w(222, 0.0);
  w[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_INPUT_ERROR(NeuralFeatureMap(shape_of(20, 10, 2), w), "neural feature-map: weight 7 is nan: must be finite");
}

// N_b = 2, N_h = 2, N_t = 2, alpha = 30: both sigmoids have scale 30 / 3 = 10.
// W1 = [[0.5, -0.25], [1, 1]], B1 = 0.1, W2 = [[0.75, -0.5], [-1, 0.25]], B2 = -0.2.
// At b = (0.2, 0.6): W1 b + B1 = (0.05, 0.9), h = (1/(1+e^-0.5), 1/(1+e^-9)) = (0.622459331, 0.999876605);
// W2 h + B2 = (-0.233093804, -0.572490180), beta = (0.088592892, 0.003253057).
TEST(NeuralFeatureMap, HandComputedTinyNetwork) {
  const std::vector<double> w = {0.5, -0.25, 1.0, 1.0, 0.1, 0.75, -0.5, -1.0, 0.25, -0.2};
  const NeuralFeatureMap map(shape_of(2, 2, 2), w);
  EXPECT_EQ(map.input_size(), 2);
  EXPECT_EQ(map.output_size(), 2);
  const Real base[] = {0.2f, 0.6f, 0.0f, 0.0f, 1.0f, 1.0f};
  Real target[6];
  map.map(base, 3, target);
  const double expected[] = {0.088592892, 0.003253057, 0.457017960, 0.000562285, 0.569585026, 0.000100337};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(target[i], expected[i], 2e-7) << "value " << i;
}

TEST(NeuralFeatureMap, ZeroWeightsGiveOneHalf) {
  const NeuralFeatureMap map(shape_of(20, 10, 2), std::vector<double>(222, 0.0));
  const RowMatrix base = uniform_rows(5, 20, 0.0f, 1.0f, 3);
  RowMatrix target(5, 2);
  map.map(base.data(), 5, target.data());
  for (Index i = 0; i < target.size(); ++i) EXPECT_EQ(target.data()[i], 0.5f);
}

class NeuralFeatureMapShapes : public ::testing::TestWithParam<NeuralFeatureMapShape> {};

TEST_P(NeuralFeatureMapShapes, AgreesWithDoublePrecisionReference) {
  const NeuralFeatureMapShape s = GetParam();
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const std::vector<double> w = uniform_weights(s.weight_count(), -1.0, 1.0, seed);
    const NeuralFeatureMap map(s, w);
    const Index count = 3 * NeuralFeatureMap::kBlockRows + 37;  // whole blocks and a partial one
    const RowMatrix base = uniform_rows(count, s.inputs, 0.0f, 1.0f, 100 + seed);
    RowMatrix target(count, s.outputs);
    map.map(base.data(), count, target.data());
    double worst = 0.0;
    for (Index r = 0; r < count; ++r) {
      const std::vector<double> expected = reference(s, w, base.row(r).data());
      for (Index t = 0; t < s.outputs; ++t) {
        worst = std::max(worst, std::abs(static_cast<double>(target(r, t)) - expected[static_cast<std::size_t>(t)]));
        ASSERT_GE(target(r, t), 0.0f);
        ASSERT_LE(target(r, t), 1.0f);
      }
    }
    EXPECT_LT(worst, 1e-5) << "seed " << seed;
  }
}

TEST_P(NeuralFeatureMapShapes, BlockEqualsRowByRowBitForBit) {
  const NeuralFeatureMapShape s = GetParam();
  const NeuralFeatureMap map(s, uniform_weights(s.weight_count(), -1.0, 1.0, 9));
  const Index count = 2 * NeuralFeatureMap::kBlockRows + 5;
  const RowMatrix base = uniform_rows(count, s.inputs, 0.0f, 1.0f, 10);
  RowMatrix block(count, s.outputs);
  map.map(base.data(), count, block.data());
  RowMatrix row(1, s.outputs);
  for (Index r = 0; r < count; ++r) {
    map.map(base.row(r).data(), 1, row.data());
    for (Index t = 0; t < s.outputs; ++t) ASSERT_EQ(row(0, t), block(r, t)) << "row " << r << " output " << t;
  }
  // Odd block sizes through the transposed entry point (padded leading dimensions) give the same
  // bits too, whether the rows are read as cached or as streamed (prefetched ahead, past the
  // array's end for the last steps).
  for (const BaseRows rows : {BaseRows::cached, BaseRows::streamed})
    for (const Index n : {Index{13}, Index{16}, Index{33}, count}) {
      const Index ld = padded_rows(n) + 5;
      std::vector<Real> base_t(static_cast<std::size_t>(s.inputs * ld), 0.0f);
      transpose_rows(base.data(), n, s.inputs, base_t.data(), ld);
      std::vector<Real> part(static_cast<std::size_t>(s.outputs * ld), -1.0f);
      map.map_transposed(base_t.data(), ld, n, part.data(), ld, rows);
      for (Index r = 0; r < n; ++r)
        for (Index t = 0; t < s.outputs; ++t)
          ASSERT_EQ(part[static_cast<std::size_t>(t * ld + r)], block(r, t)) << n << " rows, row " << r;
      EXPECT_EQ(part[static_cast<std::size_t>(padded_rows(n))], -1.0f) << "wrote past the padding";
    }
}

// The float definition the vector kernel must reproduce, one row at a time: each weight and
// bias times its layer's -alpha log2(e) / (N + 1) in double, rounded to float; each sum starts
// from the bias and adds the inputs in order by fused(), then base2_sigmoid().
std::vector<Real> float_definition(const NeuralFeatureMapShape& s, const std::vector<double>& w, const Real* b) {
  const auto nb = static_cast<std::size_t>(s.inputs);
  const auto nh = static_cast<std::size_t>(s.hidden);
  const auto nt = static_cast<std::size_t>(s.outputs);
  const double c1 = -s.alpha * 1.4426950408889634 / static_cast<double>(nb + 1);
  const double c2 = -s.alpha * 1.4426950408889634 / static_cast<double>(nh + 1);
  const auto at = [&w](std::size_t i, double c) { return static_cast<Real>(w[i] * c); };
  std::vector<Real> h(nh), out(nt);
  for (std::size_t j = 0; j < nh; ++j) {
    Real a = at(nh * nb, c1);
    for (std::size_t k = 0; k < nb; ++k) a = fused(at(j * nb + k, c1), b[k], a);
    h[j] = base2_sigmoid(a);
  }
  for (std::size_t t = 0; t < nt; ++t) {
    Real a = at(nh * nb + 1 + nt * nh, c2);
    for (std::size_t j = 0; j < nh; ++j) a = fused(at(nh * nb + 1 + t * nh + j, c2), h[j], a);
    out[t] = base2_sigmoid(a);
  }
  return out;
}

TEST_P(NeuralFeatureMapShapes, EqualsTheScalarFloatDefinitionBitForBit) {
  const NeuralFeatureMapShape s = GetParam();
  const std::vector<double> w = uniform_weights(s.weight_count(), -2.0, 2.0, 21);
  const NeuralFeatureMap map(s, w);
  for (const Index count : {Index{1}, Index{15}, Index{16}, Index{17}, Index{31}, Index{32}, Index{33}, Index{48}, Index{300}}) {
    const RowMatrix base = uniform_rows(count, s.inputs, -1.0f, 2.0f, static_cast<std::uint64_t>(count));
    RowMatrix target(count, s.outputs);
    map.map(base.data(), count, target.data());
    for (Index r = 0; r < count; ++r) {
      const std::vector<Real> want = float_definition(s, w, base.row(r).data());
      for (Index t = 0; t < s.outputs; ++t)
        ASSERT_EQ(target(r, t), want[static_cast<std::size_t>(t)]) << count << " rows, row " << r << " output " << t;
    }
  }
}

TEST_P(NeuralFeatureMapShapes, OutputsStayInUnitIntervalUnderExtremes) {
  const NeuralFeatureMapShape s = GetParam();
  for (double sign : {-1.0, 1.0}) {
    std::vector<double> w = uniform_weights(s.weight_count(), -1.0, 1.0, 11);
    for (double& x : w) x = sign * (x < 0 ? -1.0 : 1.0);  // every weight at a bound
    const NeuralFeatureMap map(s, w);
    const Index count = 300;
    RowMatrix base = uniform_rows(count, s.inputs, -1000.0f, 1000.0f, 12);
    base.row(0).setZero();
    base.row(1).setOnes();
    RowMatrix target(count, s.outputs);
    map.map(base.data(), count, target.data());
    for (Index i = 0; i < target.size(); ++i) {
      ASSERT_TRUE(std::isfinite(target.data()[i]));
      ASSERT_GE(target.data()[i], 0.0f);
      ASSERT_LE(target.data()[i], 1.0f);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PaperShapes, NeuralFeatureMapShapes,
                         ::testing::Values(shape_of(20, 10, 2), shape_of(50, 10, 4), shape_of(15, 10, 4),
                                           shape_of(3, 7, 1), shape_of(20, 13, 3), shape_of(2, 70, 2)),
                         [](const auto& test_info) {
                           return "b" + std::to_string(test_info.param.inputs) + "h" + std::to_string(test_info.param.hidden) +
                                  "t" + std::to_string(test_info.param.outputs);
                         });

TEST(TransposeRows, EqualsEigenTranspose) {
  for (Index count : {1, 7, 8, 9, 64, 203}) {
    for (Index cols : {1, 4, 8, 15, 20, 50}) {
      const RowMatrix rows = uniform_rows(count, cols, -1.0f, 1.0f, static_cast<std::uint64_t>(count * 100 + cols));
      RowMatrix out(cols, count);
      transpose_rows(rows.data(), count, cols, out.data());
      const RowMatrix want = rows.transpose();
      ASSERT_TRUE(out == want) << count << " rows of " << cols;
    }
  }
}

TEST(NeuralFeatureMap, EmptyBlockWritesNothing) {
  const NeuralFeatureMap map(shape_of(20, 10, 2), std::vector<double>(222, 0.1));
  Real target[2] = {-1.0f, -1.0f};
  map.map(nullptr, 0, target);
  EXPECT_EQ(target[0], -1.0f);
}

}  // namespace
}  // namespace qdmeta
