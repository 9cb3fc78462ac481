// Compiled with -ffp-contract=off, as cma_es.cpp: the rates and weights are part of CMA-ES's bits.
#include "qdmeta/meta/cma_es_common.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <numeric>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

double cma_sum_of_squares(const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) sum += x(i) * x(i);
  return sum;
}

void cma_set_weights_and_rates(CmaEsStrategy& s, double top) {
  const double dn = s.n;
  const int lambda = s.lambda;
  s.weights.resize(s.mu);
  for (int i = 0; i < s.mu; ++i) s.weights(i) = top - std::log(i + 1.0);
  // lambda = 1 (the paper's smallest meta-population): the one parent takes all the weight
  // (the formula gives 0 / 0 there).
  if (s.mu == 1) s.weights(0) = 1.0;
  double weight_sum = 0.0;
  for (int i = 0; i < s.mu; ++i) weight_sum += s.weights(i);
  for (int i = 0; i < s.mu; ++i) s.weights(i) /= weight_sum;
  s.mu_eff = 1.0 / cma_sum_of_squares(s.weights);
  const double mu_eff = s.mu_eff;
  s.c_sigma = (mu_eff + 2.0) / (dn + mu_eff + 5.0);
  s.d_sigma = 1.0 + 2.0 * std::max(0.0, std::sqrt((mu_eff - 1.0) / (dn + 1.0)) - 1.0) + s.c_sigma;
  s.c_c = (4.0 + mu_eff / dn) / (dn + 4.0 + 2.0 * mu_eff / dn);
  const double alpha_cov = 2.0;
  s.c1 = alpha_cov / ((dn + 1.3) * (dn + 1.3) + mu_eff);
  s.c_mu = std::min(1.0 - s.c1, alpha_cov * (mu_eff - 2.0 + 1.0 / mu_eff) /
                                    ((dn + 2.0) * (dn + 2.0) + alpha_cov * mu_eff / 2.0));
  s.chi_n = std::sqrt(dn) * (1.0 - 1.0 / (4.0 * dn) + 1.0 / (21.0 * dn * dn));
  s.eigen_interval = lambda / ((s.c1 + s.c_mu) * dn * 10.0);
}

CmaEsStrategy cma_strategy(const CmaEsParams& p) {
  const int lambda = CmaEs::sampled_population(p);
  CmaEsStrategy s;
  s.n = p.dimension;
  s.lambda = lambda;
  s.evaluated = p.population_size;
  s.library_ranking = p.population_size < 2 && p.small_population == CmaSmallPopulation::kAuthors;
  s.mu = std::max(1, lambda / 2);
  // c-cmaes's default weights, ln(mu + 1) - ln i, where its realisation of lambda = 1 is asked for.
  const double top = s.library_ranking ? std::log(s.mu + 1.0) : std::log((lambda + 1.0) / 2.0);
  cma_set_weights_and_rates(s, top);
  return s;
}

void cma_check_tell(std::string_view who, bool awaiting_tell, const Eigen::VectorXd& fitness, int expected,
                    CmaObjective objective) {
  if (!awaiting_tell) {
    throw InputError(fmt::format("{}::tell: called without a pending ask; call ask() first", who));
  }
  if (fitness.size() != expected) {
    throw InputError(fmt::format("{}::tell: expected {} fitness values, got {}", who, expected, fitness.size()));
  }
  for (Eigen::Index i = 0; i < fitness.size(); ++i) {
    if (std::isnan(fitness(i))) {
      throw InputError(fmt::format("{}::tell: fitness value {} is NaN; expected a number", who, i));
    }
  }
  if (objective != CmaObjective::kMinimise && objective != CmaObjective::kMaximise) {
    throw InputError(fmt::format("{}::tell: objective = {} is invalid; valid values: minimise, maximise", who,
                                 static_cast<int>(objective)));
  }
}

void cma_check_ranked(std::string_view who, std::span<const int> order, int lambda, int parents) {
  if (order.size() != static_cast<std::size_t>(lambda)) {
    throw InputError(fmt::format("{}::tell_ranked: expected an order of {} candidates, got {}", who, lambda, order.size()));
  }
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(lambda), 0);
  for (const int k : order) {
    if (k < 0 || k >= lambda || seen[static_cast<std::size_t>(k)]) {
      throw InputError(fmt::format("{}::tell_ranked: the order is not a permutation of 0..{} (candidate {})", who,
                                   lambda - 1, k));
    }
    seen[static_cast<std::size_t>(k)] = 1;
  }
  require_range(fmt::format("{}::tell_ranked parents", who), parents, 0, lambda);
}

void cma_rank(std::vector<int>& order, const Eigen::VectorXd& fitness, CmaObjective objective) {
  std::iota(order.begin(), order.end(), 0);
  if (objective == CmaObjective::kMinimise) {
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return fitness(a) < fitness(b); });
  } else {
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return fitness(a) > fitness(b); });
  }
}

}  // namespace qdmeta
