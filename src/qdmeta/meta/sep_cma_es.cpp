// Compiled with -ffp-contract=off and summed in fixed order, as cma_es.cpp: the same bits on
// every x86-64 CPU and at any thread count.
#include "qdmeta/meta/sep_cma_es.hpp"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/meta/cma_es_common.hpp"

namespace qdmeta {
namespace {

[[noreturn]] void invalid_state(std::string_view what) {
  throw InputError(fmt::format("SepCmaEs::set_state: {}", what));
}

template <class A, class B>
bool same(const A& a, const B& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

}  // namespace

bool operator==(const SepCmaEsState& a, const SepCmaEsState& b) {
  return same(a.mean, b.mean) && a.sigma == b.sigma && same(a.C, b.C) && same(a.p_sigma, b.p_sigma) &&
         same(a.p_c, b.p_c) && a.generation == b.generation && a.evaluations == b.evaluations &&
         a.awaiting_tell == b.awaiting_tell && same(a.samples, b.samples);
}

void SepCmaEs::validate(const CmaEsParams& params) {
  params.validate();
  if (params.rank_one != CmaRankOne::kTutorial) {
    throw InputError(fmt::format("CmaEsParams.rank_one = {} is not available in the separable CMA-ES: only "
                                 "tutorial",
                                 to_string(params.rank_one)));
  }
  if (params.population_size < 2 && params.small_population == CmaSmallPopulation::kAuthors) {
    throw InputError("CmaEsParams.small_population = authors is not available in the separable CMA-ES: use one-one");
  }
}

void SepCmaEs::separate_rates(CmaEsStrategy& s) {
  const double factor = (s.n + 2.0) / 3.0;
  s.c1 *= factor;
  s.c_mu = std::min(1.0 - s.c1, s.c_mu * factor);
  s.eigen_interval = 0.0;
}

SepCmaEsState SepCmaEs::initial_state(const CmaEsParams& params) {
  validate(params);
  const int n = params.dimension;
  SepCmaEsState s;
  if (params.x0.empty()) {
    s.mean = Eigen::VectorXd::Constant(n, params.initial_mean);
  } else {
    s.mean = Eigen::Map<const Eigen::VectorXd>(params.x0.data(), n);
  }
  s.sigma = params.initial_sigma;
  s.C = Eigen::VectorXd::Ones(n);
  s.p_sigma = Eigen::VectorXd::Zero(n);
  s.p_c = Eigen::VectorXd::Zero(n);
  s.samples = Eigen::MatrixXd::Zero(n, params.population_size);
  return s;
}

SepCmaEs::SepCmaEs(CmaEsParams params) : params_(std::move(params)) {
  validate(params_);
  strategy_ = cma_strategy(params_);
  separate_rates(strategy_);
  state_ = initial_state(params_);
  initial_ = state_;
  scale_.resize(params_.dimension);
  y_.resize(params_.dimension, strategy_.lambda);
  order_.resize(static_cast<std::size_t>(strategy_.lambda));
}

template <class FillNormals>
const Eigen::MatrixXd& SepCmaEs::ask_with(FillNormals&& fill_normals) {
  if (state_.awaiting_tell) {
    throw InputError(fmt::format("SepCmaEs::ask: called twice without tell; tell the fitness of the {} pending "
                                 "candidates first",
                                 strategy_.lambda));
  }
  const int n = params_.dimension;
  const SepCmaEsState& dist = params_.frozen ? initial_ : state_;
  for (int i = 0; i < n; ++i) scale_(i) = dist.sigma * std::sqrt(dist.C(i));
  state_.samples.resize(n, strategy_.lambda);
  const auto sample_columns = [&](int first, int count) {
    fill_normals(&state_.samples(0, first), Eigen::Index{n} * count);
    for (int k = first; k < first + count; ++k) {
      double* x = &state_.samples(0, k);
      for (int i = 0; i < n; ++i) x[i] = dist.mean(i) + scale_(i) * x[i];  // m + sigma sqrt(C) z
    }
  };
  cma_sample_within_bounds(params_, state_.samples, strategy_.lambda, sample_columns);
  state_.awaiting_tell = true;
  return state_.samples;
}

const Eigen::MatrixXd& SepCmaEs::ask(Rng& rng) { return ask_with(cma_rng_normals(rng)); }

const Eigen::MatrixXd& SepCmaEs::ask(const std::function<double()>& standard_normal) {
  return ask_with(cma_source_normals("SepCmaEs", standard_normal));
}

void SepCmaEs::tell(const Eigen::VectorXd& fitness, CmaObjective objective) {
  cma_check_tell("SepCmaEs", state_.awaiting_tell, fitness, strategy_.lambda, objective);
  state_.awaiting_tell = false;
  state_.generation += 1;
  state_.evaluations += strategy_.lambda;
  if (params_.frozen) return;
  cma_rank(order_, fitness, objective);
  update(strategy_);
}

void SepCmaEs::tell_ranked(std::span<const int> order, int parents) {
  if (!state_.awaiting_tell) {
    throw InputError("SepCmaEs::tell_ranked: called without a pending ask; call ask() first");
  }
  cma_check_ranked("SepCmaEs", order, strategy_.lambda, parents);
  state_.awaiting_tell = false;
  state_.generation += 1;
  state_.evaluations += strategy_.lambda;
  if (params_.frozen || parents == 0) return;
  std::copy(order.begin(), order.end(), order_.begin());
  CmaEsStrategy s = strategy_;
  s.mu = parents;
  cma_set_weights_and_rates(s, std::log(parents + 0.5));
  separate_rates(s);
  update(s);
}

// Hansen's tutorial's update with C diagonal: C^{-1/2} is 1 / sqrt(C_i), and the rank-one and
// rank-mu terms keep only their diagonals.
void SepCmaEs::update(const CmaEsStrategy& s) {
  SepCmaEsState& st = state_;
  const int n = s.n;
  for (int k = 0; k < s.mu; ++k) {
    const double* x = &st.samples(0, order_[static_cast<std::size_t>(k)]);
    double* y = &y_(0, k);
    for (int i = 0; i < n; ++i) y[i] = (x[i] - st.mean(i)) / st.sigma;
  }
  const double sigma_path_scale = std::sqrt(s.c_sigma * (2.0 - s.c_sigma) * s.mu_eff);
  double p_sigma_squares = 0.0;
  Eigen::VectorXd y_w = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < s.mu; ++k) {
    const double* y = &y_(0, k);
    for (int i = 0; i < n; ++i) y_w(i) += s.weights(k) * y[i];
  }
  for (int i = 0; i < n; ++i) {
    st.mean(i) += st.sigma * y_w(i);
    st.p_sigma(i) = (1.0 - s.c_sigma) * st.p_sigma(i) + sigma_path_scale * (y_w(i) / std::sqrt(st.C(i)));
    p_sigma_squares += st.p_sigma(i) * st.p_sigma(i);
  }
  const double p_sigma_norm = std::sqrt(p_sigma_squares);
  const double path_bias = std::sqrt(1.0 - std::pow(1.0 - s.c_sigma, 2.0 * static_cast<double>(st.generation)));
  const bool h_sigma = p_sigma_norm / path_bias < (1.4 + 2.0 / (n + 1.0)) * s.chi_n;
  const double c_path_scale = h_sigma ? std::sqrt(s.c_c * (2.0 - s.c_c) * s.mu_eff) : 0.0;
  const double delta_h = h_sigma ? 0.0 : s.c_c * (2.0 - s.c_c);
  const double decay = 1.0 - s.c1 - s.c_mu + s.c1 * delta_h;
  for (int i = 0; i < n; ++i) {
    st.p_c(i) = (1.0 - s.c_c) * st.p_c(i) + c_path_scale * y_w(i);
    double rank_mu = 0.0;
    for (int k = 0; k < s.mu; ++k) rank_mu += s.weights(k) * (y_(i, k) * y_(i, k));
    st.C(i) = decay * st.C(i) + s.c1 * (st.p_c(i) * st.p_c(i)) + s.c_mu * rank_mu;
  }
  st.sigma *= std::exp((s.c_sigma / s.d_sigma) * (p_sigma_norm / s.chi_n - 1.0));
}

void SepCmaEs::set_state(const SepCmaEsState& state) {
  const Eigen::Index n = params_.dimension;
  for (const auto& [name, v] : {std::pair<const char*, const Eigen::VectorXd*>{"mean", &state.mean},
                                {"C", &state.C}, {"p_sigma", &state.p_sigma}, {"p_c", &state.p_c}}) {
    if (v->size() != n) invalid_state(fmt::format("{} has size {}, expected dimension {}", name, v->size(), n));
  }
  if (!std::isfinite(state.sigma) || state.sigma <= 0.0) {
    invalid_state(fmt::format("sigma = {}, expected finite and > 0", state.sigma));
  }
  if (!(state.C.array() > 0.0).all() || !state.C.allFinite()) invalid_state("C has entries <= 0 or not finite");
  if (state.generation < 0 || state.evaluations < 0) invalid_state("counters are negative");
  const bool sized = state.samples.rows() == n && state.samples.cols() == strategy_.lambda;
  if ((state.awaiting_tell || state.samples.size() != 0) && !sized) {
    invalid_state(fmt::format("samples is {}x{}, expected {}x{}", state.samples.rows(), state.samples.cols(), n,
                              strategy_.lambda));
  }
  state_ = state;
}

void SepCmaEs::save(BinaryWriter& out) const {
  const SepCmaEsState& s = state_;
  out.tag("sep_cma_es");
  out.matrix(s.mean);
  out.value(s.sigma);
  out.matrix(s.C);
  out.matrix(s.p_sigma);
  out.matrix(s.p_c);
  out.value(s.generation);
  out.value(s.evaluations);
  out.boolean(s.awaiting_tell);
  out.matrix(s.samples);
}

void SepCmaEs::load(BinaryReader& in) {
  in.expect_tag("sep_cma_es");
  SepCmaEsState s;
  in.matrix(s.mean, "sep-CMA-ES mean");
  s.sigma = in.value<double>("sep-CMA-ES sigma");
  in.matrix(s.C, "sep-CMA-ES covariance diagonal");
  in.matrix(s.p_sigma, "sep-CMA-ES sigma path");
  in.matrix(s.p_c, "sep-CMA-ES covariance path");
  s.generation = in.value<std::int64_t>("sep-CMA-ES generation");
  s.evaluations = in.value<std::int64_t>("sep-CMA-ES evaluations");
  s.awaiting_tell = in.boolean("sep-CMA-ES pending flag");
  in.matrix(s.samples, "sep-CMA-ES samples");
  try {
    set_state(s);
  } catch (const InputError& e) {
    in.fail(e.what());
  }
}

}  // namespace qdmeta
