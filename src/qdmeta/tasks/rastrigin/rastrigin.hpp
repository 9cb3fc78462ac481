#pragma once
// The 20-D Rastrigin benchmark of the paper (docs/specification.md, Rastrigin) as pure functions of a genotype
// g in [0,1]^N, mapped to x = -5.12 + 10.24 g. Maximisation: f <= 0, optimum 0 at g = 0.5.
// The scalar functions are the reference (double); evaluate_batch is the vectorised hot path.
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <vector>

#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta::rastrigin {

inline constexpr double kBound = 5.12;          // |x| <= 5.12
inline constexpr double kDefaultScoreM = 2000;  // M: per-task scores are M + max(-M, f) > 0

inline double to_x(double g) { return fused(2.0 * kBound, g, -kBound); }

// f(g) = -[10 N + sum_i (x_i^2 - 10 cos 2 pi x_i)].
double standard(std::span<const Real> g);
// f_j: dimension j removed, N - 1 dimensions remain.
double without_dimension(std::span<const Real> g, int j);
// Standard Rastrigin of x' = a x + b; nullopt when any |x'| > 5.12 (out of range).
std::optional<double> translated(std::span<const Real> g, double a, double b);
// Dimension test: dimensions in J replaced by 10 sin(6 pi x) noise.
double dimension_test(std::span<const Real> g, std::span<const int> dims);
// Per-task score M + max(-M, f).
inline double score(double f, double m = kDefaultScoreM) { return m + (f > -m ? f : -m); }

// cos(2 pi x) for |x| < 2^22, accurate to ~1e-7 absolute; branch-free so loops vectorise.
inline Real cos_2pi(Real x) {
  constexpr Real kRound = 12582912.0f;            // 1.5 * 2^23: adding and subtracting rounds to nearest
  const Real r = x - ((x + kRound) - kRound);     // in [-0.5, 0.5]
  const Real a = std::fabs(r);                    // cos is even
  const Real t = a < 0.5f - a ? a : 0.5f - a;     // in [0, 0.25]: cos(2 pi a) = -cos(2 pi (0.5 - a))
  const Real sign = std::copysign(1.0f, 0.25f - a);
  const Real y = 6.28318530717958647f * t;        // in [0, pi/2]
  const Real y2 = y * y;
  // Taylor series to y^12 by Horner's rule: truncation error below 7e-9 on [0, pi/2].
  Real c = 1.0f / 479001600;
  c = fused(y2, c, -1.0f / 3628800);
  c = fused(y2, c, 1.0f / 40320);
  c = fused(y2, c, -1.0f / 720);
  c = fused(y2, c, 1.0f / 24);
  c = fused(y2, c, -0.5f);
  c = fused(y2, c, 1.0f);
  return sign * c;
}

// Standard Rastrigin of every row of a row-major block, in float. `scratch` holds count x N.
void evaluate_batch(const Real* genotypes, Index count, Index n, Real* fitness, std::vector<Real>& scratch);

// Linear transform x' = a x + b of the Translation meta-fitness and test.
struct LinearTransform {
  double a = 1.0;
  double b = 0.0;
  bool operator==(const LinearTransform&) const = default;
};

// Translation test grid: 12 slopes +-(1+a'), +-1/(1+a') for a' in {0.01, 0.25, 0.5} times
// 10 intercepts +-{0.01, 0.25, 0.5, 0.75, 1.0}: 120 transforms, slope-major.
std::vector<LinearTransform> translation_test_grid();
// Translation meta-fitness transforms: `repetitions` from each of 8 ranges (sign of a x
// shrink |a| = 1/U(1,1.1) or expand |a| = U(1,1.1) x sign of b in [-0.5,0] or [0,0.5]).
std::vector<LinearTransform> sample_meta_transforms(Rng& rng, int repetitions = 2);
// `count` distinct unordered pairs of dimensions out of n (Dimension test).
std::vector<std::array<int, 2>> sample_dimension_pairs(Rng& rng, int n, int count);
// `count` distinct dimensions out of n (Dimension meta-fitness).
std::vector<int> sample_dimensions(Rng& rng, int n, int count);

}  // namespace qdmeta::rastrigin
