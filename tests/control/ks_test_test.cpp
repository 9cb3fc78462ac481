// The two-sample Kolmogorov-Smirnov statistic and critical value against hand-computed
// examples and an independent brute-force evaluation of the two empirical CDFs.
#include "qdmeta/control/ks_test.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

TEST(KsStatistic, HandComputedExamples) {
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{1, 2, 3}, std::vector<double>{4, 5, 6}), 1.0);
  // F_a - F_b at 1..6: .25, .5, .5, .5, .25, 0.
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{1, 2, 3, 4}, std::vector<double>{3, 4, 5, 6}), 0.5);
  // Interleaved samples of sizes 3 and 4: the largest gap is 1/3, at 0.1 and at 0.6.
  EXPECT_NEAR(ks_statistic(std::vector<double>{0.1, 0.4, 0.7}, std::vector<double>{0.2, 0.3, 0.5, 0.6}), 1.0 / 3.0,
              1e-15);
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{2, 5, 7}, std::vector<double>{2, 5, 7}), 0.0);
}

TEST(KsStatistic, TiesStepBothDistributionsTogether) {
  // At x = 1: F_a = 2/3, F_b = 1/3; at x = 2 both are 1. A walk that steps one sample at a
  // time would see 2/3 - 0 first and report 2/3.
  EXPECT_NEAR(ks_statistic(std::vector<double>{1, 1, 2}, std::vector<double>{1, 2, 2}), 1.0 / 3.0, 1e-15);
  EXPECT_DOUBLE_EQ(ks_statistic(std::vector<double>{0, 0, 0}, std::vector<double>{0, 0}), 0.0);
}

double brute_force_ks(const std::vector<double>& a, const std::vector<double>& b) {
  const auto cdf = [](const std::vector<double>& s, double x) {
    return static_cast<double>(std::count_if(s.begin(), s.end(), [x](double v) { return v <= x; })) /
           static_cast<double>(s.size());
  };
  double d = 0.0;
  for (const auto* s : {&a, &b})
    for (double x : *s) d = std::max(d, std::abs(cdf(a, x) - cdf(b, x)));
  return d;
}

TEST(KsStatistic, AgreesWithBruteForceOnRandomSamplesWithTies) {
  Rng rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> a(1 + rng.below(40)), b(1 + rng.below(40));
    for (double& v : a) v = static_cast<double>(rng.below(12));  // few distinct values: many ties
    for (double& v : b) v = static_cast<double>(rng.below(12)) + (trial % 3 == 0 ? 2.0 : 0.0);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_NEAR(ks_statistic(a, b), brute_force_ks(a, b), 1e-12) << "trial " << trial;
  }
}

TEST(KsCriticalValue, MatchesTheTabulatedCoefficients) {
  // c(0.05) = sqrt(-ln(0.025) / 2) = 1.358101; sqrt(20 / 100) = 0.4472136.
  EXPECT_NEAR(ks_critical_value(10, 10, 0.05), 1.358101 * 0.4472136, 1e-6);
  // c(0.01) = 1.627624; n = 30, m = 50: sqrt(80 / 1500) = 0.2309401.
  EXPECT_NEAR(ks_critical_value(30, 50, 0.01), 1.627624 * 0.2309401, 1e-6);
  EXPECT_THROW(ks_critical_value(0, 5, 0.05), Error);
  EXPECT_THROW(ks_critical_value(5, 5, 0.0), Error);
  EXPECT_THROW(ks_statistic(std::vector<double>{}, std::vector<double>{1.0}), Error);
}

}  // namespace
}  // namespace qdmeta
