#pragma once
// What the full and the separable CMA-ES (cma_es.hpp, sep_cma_es.hpp) share: the recombination
// weights and learning rates, the ask/tell protocol's checks, the ranking of a batch by fitness
// and the bounds handling of ask(). Both compile with -ffp-contract=off and sum in fixed order.
#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <span>
#include <string_view>
#include <vector>

#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace qdmeta {

// The weights top - ln i for s.mu parents, normalised, and the learning rates of the tutorial's
// Table 1 for them (s.n and s.lambda set); eigen_interval is the tutorial's.
void cma_set_weights_and_rates(CmaEsStrategy& s, double top);

// The strategy of a (mu/mu_W, lambda) run of these params: mu = floor(lambda / 2), weights
// ln((lambda + 1) / 2) - ln i (the authors' small-population realisation aside).
CmaEsStrategy cma_strategy(const CmaEsParams& params);

// x . x summed in index order.
double cma_sum_of_squares(const Eigen::VectorXd& x);

// tell()'s checks, `who` naming the class ("CmaEs"): a pending ask, `expected` values, no NaN, a
// known objective. InputError otherwise.
void cma_check_tell(std::string_view who, bool awaiting_tell, const Eigen::VectorXd& fitness, int expected,
                    CmaObjective objective);

// tell_ranked()'s checks of the order (a permutation of 0..lambda-1) and of parents (0..lambda).
void cma_check_ranked(std::string_view who, std::span<const int> order, int lambda, int parents);

// order = the candidates best first; stable, so that ties keep ask() order.
void cma_rank(std::vector<int>& order, const Eigen::VectorXd& fitness, CmaObjective objective);

// ask()'s sources of normals, fill(out, count) writing `count` N(0, 1) draws: one from Rng::normal(),
// and one from any per-draw source (InputError naming `who` when it is empty).
inline auto cma_rng_normals(Rng& rng) {
  return [&rng](double* out, Eigen::Index count) {
    for (Eigen::Index i = 0; i < count; ++i) out[i] = rng.normal();
  };
}
inline auto cma_source_normals(std::string_view who, const std::function<double()>& standard_normal) {
  if (!standard_normal) throw InputError(fmt::format("{}::ask: the standard-normal source is empty", who));
  return [&standard_normal](double* out, Eigen::Index count) {
    for (Eigen::Index i = 0; i < count; ++i) out[i] = standard_normal();
  };
}

// ask()'s bounds: sample_columns(first, count) writes `count` candidates from column `first` of
// `samples`; with kResample each of the first `bounded` columns is redrawn until it lies inside
// (max_resample_attempts draws in all), then the first `bounded` columns are clamped (unless kNone).
template <class SampleColumns>
void cma_sample_within_bounds(const CmaEsParams& p, Eigen::MatrixXd& samples, int bounded,
                              SampleColumns&& sample_columns) {
  const auto lambda = static_cast<int>(samples.cols());
  const double lo = p.lower_bound;
  const double hi = p.upper_bound;
  if (p.bounds == CmaBoundsHandling::kResample) {
    const auto inside = [&](int column) {
      const auto x = samples.col(column).array();
      return (x >= lo).all() && (x <= hi).all();
    };
    for (int k = 0; k < lambda; ++k) {
      sample_columns(k, 1);
      for (int attempt = 1; attempt < p.max_resample_attempts && k < bounded && !inside(k); ++attempt) {
        sample_columns(k, 1);
      }
    }
  } else {
    sample_columns(0, lambda);
  }
  if (p.bounds != CmaBoundsHandling::kNone) {
    double* x = samples.data();
    const Eigen::Index count = samples.rows() * bounded;
    for (Eigen::Index i = 0; i < count; ++i) x[i] = std::min(std::max(x[i], lo), hi);
  }
}

}  // namespace qdmeta
