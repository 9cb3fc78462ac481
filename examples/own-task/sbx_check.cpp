// sbx-check: the example's SBX operator (sbx.cpp) against its definition. For fixed parent and
// partner genes the distribution function of an offspring's gene has a closed form: the parent's
// gene with probability 1/2, else the lower or the upper child with probability 1/4 each, their
// spread factors drawn from SBX's distribution truncated where the child would leave [0, 1]. The
// empirical distribution of many offspring must match it at every point checked to within five
// standard errors. Exit status 0 when it does (scripts/test-installed-package.sh runs it).
#include <qdmeta/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sbx.hpp"

namespace {

// SBX's spread factor beta: its distribution function, from the density (eta + 1) / 2 beta^eta
// below 1 and (eta + 1) / 2 beta^-(eta + 2) above.
double spread_cdf(double beta, double eta) {
  if (beta <= 0) return 0;
  return beta <= 1 ? 0.5 * std::pow(beta, eta + 1) : 1 - 0.5 * std::pow(beta, -(eta + 1));
}
// The same truncated to [0, max_spread].
double truncated_cdf(double beta, double eta, double max_spread) {
  return spread_cdf(std::min(beta, max_spread), eta) / spread_cdf(max_spread, eta);
}

// P(offspring gene <= t) for parent gene x and partner gene y (x != y).
double offspring_cdf(double t, double x, double y, double eta) {
  const double lo = std::min(x, y), hi = std::max(x, y), d = hi - lo, mean = (lo + hi) / 2;
  // lower child = mean - beta d / 2 <= t when beta >= 2 (mean - t) / d; upper = mean + beta d / 2.
  const double lower = 1 - truncated_cdf(2 * (mean - t) / d, eta, 1 + 2 * lo / d);
  const double upper = truncated_cdf(2 * (t - mean) / d, eta, 1 + 2 * (1 - hi) / d);
  return 0.5 * (x <= t ? 1 : 0) + 0.25 * lower + 0.25 * upper;
}

}  // namespace

int main() {
  constexpr qdmeta::Index kRows = 400'000;
  constexpr double kEta = 1;  // a small index spreads the children far, so the truncation shows
  // Column 0: parents at the lower bound; 1: in the middle; 2: equal genes, whose offspring is them.
  const std::vector<double> parent = {0.0, 0.5625, 0.3}, partner = {0.25, 0.4375, 0.3};
  const std::vector<std::vector<double>> points = {{0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.8},
                                                   {0.1, 0.3, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 0.9}};
  const auto genes = static_cast<qdmeta::Index>(parent.size());
  qdmeta::RowMatrix parents(kRows, genes), partners(kRows, genes), offspring(kRows, genes);
  for (qdmeta::Index k = 0; k < genes; ++k) {
    parents.col(k).setConstant(static_cast<qdmeta::Real>(parent[static_cast<std::size_t>(k)]));
    partners.col(k).setConstant(static_cast<qdmeta::Real>(partner[static_cast<std::size_t>(k)]));
  }
  arm::sbx(kEta)(parents, partners, /*seed=*/7, offspring);

  int failures = 0;
  for (std::size_t k = 0; k < points.size(); ++k)
    for (const double t : points[k]) {
      const double expected = offspring_cdf(t, parent[k], partner[k], kEta);
      const auto below = (offspring.col(static_cast<qdmeta::Index>(k)).array() <= static_cast<qdmeta::Real>(t)).count();
      const double measured = static_cast<double>(below) / kRows;
      const double tolerance = 5 * std::sqrt(expected * (1 - expected) / kRows) + 1e-9;
      if (std::abs(measured - expected) > tolerance) {
        std::printf("sbx-check: gene %zu: P(offspring <= %g) = %.5f, expected %.5f (+- %.5f)\n", k, t, measured, expected,
                    tolerance);
        ++failures;
      }
    }
  if ((offspring.col(2).array() != static_cast<qdmeta::Real>(parent[2])).any()) {
    std::printf("sbx-check: equal genes gave an offspring gene that differs from them\n");
    ++failures;
  }
  if (failures == 0) std::printf("sbx-check: the offspring's distribution matches SBX's at every point checked\n");
  return failures == 0 ? 0 : 1;
}
