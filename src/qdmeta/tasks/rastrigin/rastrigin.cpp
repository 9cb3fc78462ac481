#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta::rastrigin {
namespace {

double term(double x) { return x * x - 10.0 * std::cos(2.0 * std::numbers::pi * x); }

// x^2 - 10 cos(2 pi x) for every gene of a block; restrict lets the compiler vectorise
// without a runtime overlap check.
void rastrigin_terms(const Real* __restrict genes, Real* __restrict terms, Index total) {
  for (Index k = 0; k < total; ++k) {
    const Real x = fused(static_cast<Real>(2 * kBound), genes[k], static_cast<Real>(-kBound));
    terms[k] = fused(x, x, -10.0f * cos_2pi(x));
  }
}

}  // namespace

double standard(std::span<const Real> g) {
  double sum = 0.0;
  for (Real gi : g) sum += term(to_x(gi));
  return -(10.0 * static_cast<double>(g.size()) + sum);
}

double without_dimension(std::span<const Real> g, int j) {
  double sum = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (static_cast<int>(i) != j) sum += term(to_x(g[i]));
  return -(10.0 * static_cast<double>(g.size() - 1) + sum);
}

std::optional<double> translated(std::span<const Real> g, double a, double b) {
  double sum = 0.0;
  for (Real gi : g) {
    const double x = fused(a, to_x(gi), b);  // as the Translation meta-fitness computes it
    if (std::abs(x) > kBound) return std::nullopt;
    sum += term(x);
  }
  return -(10.0 * static_cast<double>(g.size()) + sum);
}

double dimension_test(std::span<const Real> g, std::span<const int> dims) {
  double sum = 0.0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double x = to_x(g[i]);
    const bool removed = std::find(dims.begin(), dims.end(), static_cast<int>(i)) != dims.end();
    sum += removed ? -10.0 * std::sin(6.0 * std::numbers::pi * x) : term(x);
  }
  return -(10.0 * static_cast<double>(g.size() - dims.size()) + sum);
}

void evaluate_batch(const Real* genotypes, Index count, Index n, Real* fitness, std::vector<Real>& scratch) {
  const Index total = count * n;
  scratch.resize(static_cast<std::size_t>(total));
  Real* terms = scratch.data();
  rastrigin_terms(genotypes, terms, total);  // element-wise over the contiguous block
  // Row sums in a fixed order, with four accumulators for instruction-level parallelism.
  const Real base = 10.0f * static_cast<Real>(n);
  for (Index r = 0; r < count; ++r) {
    const Real* t = terms + r * n;
    Real s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    Index j = 0;
    for (; j + 4 <= n; j += 4) {
      s0 += t[j];
      s1 += t[j + 1];
      s2 += t[j + 2];
      s3 += t[j + 3];
    }
    for (; j < n; ++j) s0 += t[j];
    fitness[r] = -(base + ((s0 + s1) + (s2 + s3)));
  }
}

std::vector<LinearTransform> translation_test_grid() {
  std::vector<LinearTransform> grid;
  const double primes[] = {0.01, 0.25, 0.5};
  const double intercepts[] = {0.01, 0.25, 0.5, 0.75, 1.0};
  for (double ap : primes)
    for (bool shrink : {false, true})
      for (bool reverse : {false, true}) {
        const double magnitude = shrink ? 1.0 / (1.0 + ap) : 1.0 + ap;
        const double a = reverse ? -magnitude : magnitude;
        for (double sign : {1.0, -1.0})
          for (double b : intercepts) grid.push_back({a, sign * b});
      }
  return grid;
}

std::vector<LinearTransform> sample_meta_transforms(Rng& rng, int repetitions) {
  std::vector<LinearTransform> out;
  for (bool negative_a : {true, false})
    for (bool shrink : {false, true})
      for (bool negative_b : {true, false})
        for (int r = 0; r < repetitions; ++r) {
          const double u = rng.uniform(1.0, 1.1);
          double a = shrink ? 1.0 / u : u;
          if (negative_a) a = -a;
          const double b = negative_b ? rng.uniform(-0.5, 0.0) : rng.uniform(0.0, 0.5);
          out.push_back({a, b});
        }
  return out;
}

std::vector<std::array<int, 2>> sample_dimension_pairs(Rng& rng, int n, int count) {
  std::vector<std::array<int, 2>> all;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) all.push_back({i, j});
  if (count < 0 || static_cast<std::size_t>(count) > all.size())
    throw InputError(fmt::format("cannot draw {} distinct dimension pairs out of {} dimensions ({} pairs exist)",
                                 count, n, all.size()));
  choose_without_replacement(all, static_cast<std::size_t>(count), rng);
  return all;
}

std::vector<int> sample_dimensions(Rng& rng, int n, int count) {
  if (count < 0 || count > n)
    throw InputError(fmt::format("cannot draw {} distinct dimensions out of {}", count, n));
  std::vector<int> all(static_cast<std::size_t>(n));
  std::iota(all.begin(), all.end(), 0);
  choose_without_replacement(all, static_cast<std::size_t>(count), rng);
  return all;
}

}  // namespace qdmeta::rastrigin
