// GCC 12 reports false -Wmaybe-uninitialized warnings inside Eigen 3.4's tridiagonalisation
// (used by SelfAdjointEigenSolver) when Eigen is included with -I rather than as a system
// header. The warnings are located in Eigen's headers, so silence them only there.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop
#endif

#include "qdmeta/meta/cma_es.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>
#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

// Shortest round-trip text of a double ("0.5", "nan", "-inf").
std::string format_double(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

[[noreturn]] void invalid_param(const std::string& field, const std::string& value,
                                const std::string& rule) {
  throw InputError("CmaEsParams." + field + " = " + value + " is invalid: " + rule);
}

[[noreturn]] void invalid_state(const std::string& what) {
  throw InputError("CmaEs::set_state: " + what);
}

std::string shape(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + "x" + std::to_string(cols);
}

// Eigen's operator== asserts on a size mismatch; states of different sizes are just unequal.
template <class A, class B>
bool same(const A& a, const B& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

CmaEsStrategy make_strategy(int n, int lambda) {
  CmaEsStrategy s;
  s.n = n;
  s.lambda = lambda;
  s.mu = std::max(1, lambda / 2);
  const double dn = n;
  s.weights.resize(s.mu);
  for (int i = 0; i < s.mu; ++i) {
    s.weights(i) = std::log((lambda + 1.0) / 2.0) - std::log(i + 1.0);
  }
  // lambda = 1 (the paper's smallest meta-population): the one parent takes all the weight
  // (the formula gives 0 / 0 there).
  if (s.mu == 1) s.weights(0) = 1.0;
  s.weights /= s.weights.sum();
  s.mu_eff = 1.0 / s.weights.squaredNorm();
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
  return s;
}

}  // namespace

std::string to_string(CmaBoundsHandling value) {
  switch (value) {
    case CmaBoundsHandling::kNone: return "none";
    case CmaBoundsHandling::kClamp: return "clamp";
    case CmaBoundsHandling::kResample: return "resample";
  }
  return "unknown(" + std::to_string(static_cast<int>(value)) + ")";
}

CmaBoundsHandling cma_bounds_handling_from_string(std::string_view text) {
  for (auto value : {CmaBoundsHandling::kNone, CmaBoundsHandling::kClamp,
                     CmaBoundsHandling::kResample}) {
    if (text == to_string(value)) return value;
  }
  throw InputError("unknown CMA-ES bounds handling \"" + std::string(text) +
                   "\"; valid values: none, clamp, resample");
}

std::string to_string(CmaObjective value) {
  switch (value) {
    case CmaObjective::kMinimise: return "minimise";
    case CmaObjective::kMaximise: return "maximise";
  }
  return "unknown(" + std::to_string(static_cast<int>(value)) + ")";
}

CmaObjective cma_objective_from_string(std::string_view text) {
  for (auto value : {CmaObjective::kMinimise, CmaObjective::kMaximise}) {
    if (text == to_string(value)) return value;
  }
  throw InputError("unknown CMA-ES objective \"" + std::string(text) +
                   "\"; valid values: minimise, maximise");
}

void CmaEsParams::validate() const {
  if (dimension < 1) invalid_param("dimension", std::to_string(dimension), "must be >= 1");
  if (population_size < 1) invalid_param("population_size", std::to_string(population_size), "must be >= 1");
  if (!std::isfinite(initial_sigma) || initial_sigma <= 0.0) {
    invalid_param("initial_sigma", format_double(initial_sigma), "must be finite and > 0");
  }
  if (!std::isfinite(initial_mean)) {
    invalid_param("initial_mean", format_double(initial_mean), "must be finite");
  }
  if (!x0.empty() && x0.size() != static_cast<std::size_t>(dimension)) {
    invalid_param("x0", "a vector of size " + std::to_string(x0.size()),
                  "must be empty or have dimension = " + std::to_string(dimension) + " entries");
  }
  for (std::size_t i = 0; i < x0.size(); ++i) {
    if (!std::isfinite(x0[i])) {
      invalid_param("x0[" + std::to_string(i) + "]", format_double(x0[i]), "must be finite");
    }
  }
  if (bounds != CmaBoundsHandling::kNone && bounds != CmaBoundsHandling::kClamp &&
      bounds != CmaBoundsHandling::kResample) {
    invalid_param("bounds", to_string(bounds), "must be one of none, clamp, resample");
  }
  if (max_resample_attempts < 1) {
    invalid_param("max_resample_attempts", std::to_string(max_resample_attempts),
                  "must be >= 1");
  }
  if (bounds == CmaBoundsHandling::kNone) return;
  if (!std::isfinite(lower_bound)) {
    invalid_param("lower_bound", format_double(lower_bound), "must be finite");
  }
  if (!std::isfinite(upper_bound) || upper_bound <= lower_bound) {
    invalid_param("upper_bound", format_double(upper_bound),
                  "must be finite and > lower_bound = " + format_double(lower_bound));
  }
  const auto check_inside = [&](const std::string& field, double value) {
    if (value < lower_bound || value > upper_bound) {
      invalid_param(field, format_double(value),
                    "must lie in [lower_bound, upper_bound] = [" + format_double(lower_bound) +
                        ", " + format_double(upper_bound) + "] when bounds = " +
                        to_string(bounds));
    }
  };
  if (x0.empty()) check_inside("initial_mean", initial_mean);
  for (std::size_t i = 0; i < x0.size(); ++i) check_inside("x0[" + std::to_string(i) + "]", x0[i]);
}

bool operator==(const CmaEsState& a, const CmaEsState& b) {
  return same(a.mean, b.mean) && a.sigma == b.sigma && same(a.C, b.C) && same(a.B, b.B) &&
         same(a.D, b.D) && same(a.p_sigma, b.p_sigma) && same(a.p_c, b.p_c) &&
         a.generation == b.generation && a.evaluations == b.evaluations &&
         a.eigen_evaluations == b.eigen_evaluations && a.decompositions == b.decompositions &&
         a.awaiting_tell == b.awaiting_tell && same(a.samples, b.samples);
}

CmaEsState CmaEs::initial_state(const CmaEsParams& params) {
  params.validate();
  const int n = params.dimension;
  CmaEsState s;
  if (params.x0.empty()) {
    s.mean = Eigen::VectorXd::Constant(n, params.initial_mean);
  } else {
    s.mean = Eigen::Map<const Eigen::VectorXd>(params.x0.data(), n);
  }
  s.sigma = params.initial_sigma;
  s.C = Eigen::MatrixXd::Identity(n, n);
  s.B = Eigen::MatrixXd::Identity(n, n);
  s.D = Eigen::VectorXd::Ones(n);
  s.p_sigma = Eigen::VectorXd::Zero(n);
  s.p_c = Eigen::VectorXd::Zero(n);
  s.samples = Eigen::MatrixXd::Zero(n, params.population_size);
  return s;
}

CmaEs::CmaEs(CmaEsParams params) : params_(std::move(params)) {
  params_.validate();
  strategy_ = make_strategy(params_.dimension, params_.population_size);
  state_ = initial_state(params_);
  initial_ = state_;
  z_.resize(params_.dimension);
  y_.resize(params_.dimension, strategy_.mu);
  order_.resize(static_cast<std::size_t>(params_.population_size));
}

void CmaEs::sample_column(int column, const std::function<double()>& standard_normal) {
  const CmaEsState& dist = params_.frozen ? initial_ : state_;
  for (Eigen::Index i = 0; i < z_.size(); ++i) z_(i) = dist.D(i) * standard_normal();
  state_.samples.col(column).noalias() = dist.B * z_;
  state_.samples.col(column) = dist.mean + dist.sigma * state_.samples.col(column);
}

const Eigen::MatrixXd& CmaEs::ask(const std::function<double()>& standard_normal) {
  if (state_.awaiting_tell) {
    throw InputError("CmaEs::ask: called twice without tell; tell the fitness of the " +
                     std::to_string(params_.population_size) + " pending candidates first");
  }
  if (!standard_normal) throw InputError("CmaEs::ask: the standard-normal source is empty");
  const int n = params_.dimension;
  const int lambda = params_.population_size;
  state_.samples.resize(n, lambda);
  const double lo = params_.lower_bound;
  const double hi = params_.upper_bound;
  const auto inside = [&](int column) {
    const auto x = state_.samples.col(column).array();
    return (x >= lo).all() && (x <= hi).all();
  };
  for (int k = 0; k < lambda; ++k) {
    sample_column(k, standard_normal);
    if (params_.bounds == CmaBoundsHandling::kResample) {
      for (int attempt = 1; attempt < params_.max_resample_attempts && !inside(k); ++attempt) {
        sample_column(k, standard_normal);
      }
    }
  }
  if (params_.bounds != CmaBoundsHandling::kNone) {
    state_.samples = state_.samples.cwiseMax(lo).cwiseMin(hi);
  }
  state_.awaiting_tell = true;
  return state_.samples;
}

void CmaEs::tell(const Eigen::VectorXd& fitness, CmaObjective objective) {
  const int lambda = params_.population_size;
  if (!state_.awaiting_tell) {
    throw InputError("CmaEs::tell: called without a pending ask; call ask() first");
  }
  if (fitness.size() != lambda) {
    throw InputError("CmaEs::tell: expected " + std::to_string(lambda) + " fitness values, got " +
                     std::to_string(fitness.size()));
  }
  for (Eigen::Index i = 0; i < fitness.size(); ++i) {
    if (std::isnan(fitness(i))) {
      throw InputError("CmaEs::tell: fitness value " + std::to_string(i) +
                       " is NaN; expected a number");
    }
  }
  if (objective != CmaObjective::kMinimise && objective != CmaObjective::kMaximise) {
    throw InputError("CmaEs::tell: objective = " + to_string(objective) +
                     " is invalid; valid values: minimise, maximise");
  }
  state_.awaiting_tell = false;
  state_.generation += 1;
  state_.evaluations += lambda;
  if (params_.frozen) return;

  const CmaEsStrategy& s = strategy_;
  CmaEsState& st = state_;
  // Rank the candidates, best first; stable so that ties keep ask() order.
  std::iota(order_.begin(), order_.end(), 0);
  if (objective == CmaObjective::kMinimise) {
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return fitness(a) < fitness(b); });
  } else {
    std::stable_sort(order_.begin(), order_.end(),
                     [&](int a, int b) { return fitness(a) > fitness(b); });
  }
  // Steps of the mu best, recomputed from the returned (possibly clamped) points.
  for (int i = 0; i < s.mu; ++i) {
    y_.col(i) = (st.samples.col(order_[static_cast<std::size_t>(i)]) - st.mean) / st.sigma;
  }
  const Eigen::VectorXd y_w = y_ * s.weights;
  st.mean += st.sigma * y_w;  // c_m = 1

  // Cumulative step-size adaptation with C^{-1/2} = B D^{-1} B^T from the last decomposition.
  const Eigen::VectorXd c_inv_sqrt_y_w = st.B * (st.B.transpose() * y_w).cwiseQuotient(st.D);
  st.p_sigma = (1.0 - s.c_sigma) * st.p_sigma +
               std::sqrt(s.c_sigma * (2.0 - s.c_sigma) * s.mu_eff) * c_inv_sqrt_y_w;
  const double p_sigma_norm = st.p_sigma.norm();
  const double n = s.n;
  const double path_bias =
      std::sqrt(1.0 - std::pow(1.0 - s.c_sigma, 2.0 * static_cast<double>(st.generation)));
  const bool h_sigma = p_sigma_norm / path_bias < (1.4 + 2.0 / (n + 1.0)) * s.chi_n;
  st.p_c = (1.0 - s.c_c) * st.p_c;
  if (h_sigma) st.p_c += std::sqrt(s.c_c * (2.0 - s.c_c) * s.mu_eff) * y_w;

  // Rank-one + rank-mu update; the weights sum to 1. Only the lower triangle is computed.
  const double delta_h = h_sigma ? 0.0 : s.c_c * (2.0 - s.c_c);
  st.C *= 1.0 - s.c1 - s.c_mu + s.c1 * delta_h;
  auto lower = st.C.selfadjointView<Eigen::Lower>();
  lower.rankUpdate(st.p_c, s.c1);
  y_ = y_ * s.weights.cwiseSqrt().asDiagonal();
  lower.rankUpdate(y_, s.c_mu);
  st.C.triangularView<Eigen::StrictlyUpper>() = st.C.transpose();

  st.sigma *= std::exp((s.c_sigma / s.d_sigma) * (p_sigma_norm / s.chi_n - 1.0));

  if (static_cast<double>(st.evaluations - st.eigen_evaluations) > s.eigen_interval) decompose();
}

void CmaEs::decompose() {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(state_.C);
  if (solver.info() != Eigen::Success) {
    throw Error("CmaEs: eigendecomposition of the covariance matrix failed at generation " +
                std::to_string(state_.generation));
  }
  // Rounding can push tiny eigenvalues to or below zero; keep C^{-1/2} finite.
  const Eigen::VectorXd& eigenvalues = solver.eigenvalues();
  const double floor = std::max(eigenvalues.maxCoeff(), 1e-300) * 1e-20;
  state_.D = eigenvalues.cwiseMax(floor).cwiseSqrt();
  state_.B = solver.eigenvectors();
  state_.eigen_evaluations = state_.evaluations;
  state_.decompositions += 1;
}

void CmaEs::set_state(const CmaEsState& state) {
  const Eigen::Index n = params_.dimension;
  const Eigen::Index lambda = params_.population_size;
  const auto check_vector = [&](const char* name, const Eigen::VectorXd& v) {
    if (v.size() != n) {
      invalid_state(std::string(name) + " has size " + std::to_string(v.size()) +
                    ", expected dimension " + std::to_string(n));
    }
  };
  const auto check_square = [&](const char* name, const Eigen::MatrixXd& m) {
    if (m.rows() != n || m.cols() != n) {
      invalid_state(std::string(name) + " is " + shape(m.rows(), m.cols()) + ", expected " +
                    shape(n, n));
    }
  };
  check_vector("mean", state.mean);
  check_vector("D", state.D);
  check_vector("p_sigma", state.p_sigma);
  check_vector("p_c", state.p_c);
  check_square("C", state.C);
  check_square("B", state.B);
  if (!std::isfinite(state.sigma) || state.sigma <= 0.0) {
    invalid_state("sigma = " + format_double(state.sigma) + ", expected finite and > 0");
  }
  if (!(state.D.array() > 0.0).all()) invalid_state("D has entries <= 0, expected all > 0");
  if (state.generation < 0 || state.evaluations < 0 || state.eigen_evaluations < 0 ||
      state.decompositions < 0 || state.eigen_evaluations > state.evaluations) {
    invalid_state("counters are inconsistent (negative, or eigen_evaluations > evaluations)");
  }
  const bool sized = state.samples.rows() == n && state.samples.cols() == lambda;
  if ((state.awaiting_tell || state.samples.size() != 0) && !sized) {
    invalid_state("samples is " + shape(state.samples.rows(), state.samples.cols()) +
                  ", expected " + shape(n, lambda));
  }
  state_ = state;
}


void CmaEs::save(BinaryWriter& out) const {
  const CmaEsState& s = state_;
  out.tag("cma_es");
  out.matrix(s.mean);
  out.value(s.sigma);
  out.matrix(s.C);
  out.matrix(s.B);
  out.matrix(s.D);
  out.matrix(s.p_sigma);
  out.matrix(s.p_c);
  out.value(s.generation);
  out.value(s.evaluations);
  out.value(s.eigen_evaluations);
  out.value(s.decompositions);
  out.boolean(s.awaiting_tell);
  out.matrix(s.samples);
}

void CmaEs::load(BinaryReader& in) {
  in.expect_tag("cma_es");
  CmaEsState s;
  in.matrix(s.mean, "CMA-ES mean");
  s.sigma = in.value<double>("CMA-ES sigma");
  in.matrix(s.C, "CMA-ES covariance");
  in.matrix(s.B, "CMA-ES eigenvectors");
  in.matrix(s.D, "CMA-ES eigenvalues");
  in.matrix(s.p_sigma, "CMA-ES sigma path");
  in.matrix(s.p_c, "CMA-ES covariance path");
  s.generation = in.value<std::int64_t>("CMA-ES generation");
  s.evaluations = in.value<std::int64_t>("CMA-ES evaluations");
  s.eigen_evaluations = in.value<std::int64_t>("CMA-ES decomposition time");
  s.decompositions = in.value<std::int64_t>("CMA-ES decompositions");
  s.awaiting_tell = in.boolean("CMA-ES pending flag");
  in.matrix(s.samples, "CMA-ES samples");
  try {
    set_state(s);
  } catch (const InputError& e) {
    in.fail(e.what());
  }
}

}  // namespace qdmeta
