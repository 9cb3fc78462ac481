// Every sum in this file runs in a fixed order over plain loops, and the file is compiled with
// -ffp-contract=off: CMA-ES's bits (and so QD-Meta's results) are then the same on every x86-64
// CPU, whatever vector width Eigen or the compiler would pick there (docs/architecture.md,
// "Bit-identical across machines"). Eigen holds the data; it does no arithmetic here.
#include "qdmeta/meta/cma_es.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "qdmeta/core/error.hpp"
#include "qdmeta/meta/cma_es_common.hpp"
#include "qdmeta/meta/symmetric_eigen.hpp"

namespace qdmeta {
namespace {

// Messages for a rule that core/params.hpp's require_* helpers do not express (fmt prints a
// double in its shortest round-trip form: "0.5", "nan", "-inf").
template <class Value>
[[noreturn]] void invalid_param(std::string_view field, const Value& value, std::string_view rule) {
  throw InputError(fmt::format("CmaEsParams.{} = {} is invalid: {}", field, value, rule));
}

[[noreturn]] void invalid_state(std::string_view what) {
  throw InputError(fmt::format("CmaEs::set_state: {}", what));
}

std::string shape(Eigen::Index rows, Eigen::Index cols) { return fmt::format("{}x{}", rows, cols); }

// y = A x, summed over the columns of A in order (each y_i is a sum in j = 0, 1, ...).
void multiply(const Eigen::MatrixXd& a, const double* x, double* y) {
  const Eigen::Index rows = a.rows();
  std::fill_n(y, rows, 0.0);
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const double* column = &a(0, j);
    const double xj = x[j];
    for (Eigen::Index i = 0; i < rows; ++i) y[i] += column[i] * xj;
  }
}

// Y = A X for `count` columns of X (rows a.cols()) into Y (rows a.rows()): each y_ik is the sum
// over j = 0, 1, ... as multiply() forms it, with A read once for all the columns.
void multiply_columns(const Eigen::MatrixXd& a, const double* x, double* y, Eigen::Index count) {
  const Eigen::Index rows = a.rows();
  const Eigen::Index inner = a.cols();
  std::fill_n(y, rows * count, 0.0);
  for (Eigen::Index j = 0; j < inner; ++j) {
    const double* column = &a(0, j);
    for (Eigen::Index k = 0; k < count; ++k) {
      const double xj = x[k * inner + j];
      double* yk = y + k * rows;
      for (Eigen::Index i = 0; i < rows; ++i) yk[i] += column[i] * xj;
    }
  }
}

// y = A^T x: each y_j is the dot product of column j with x, summed in i = 0, 1, ...
void multiply_transposed(const Eigen::MatrixXd& a, const double* x, double* y) {
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const double* column = &a(0, j);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < a.rows(); ++i) sum += column[i] * x[i];
    y[j] = sum;
  }
}

// Eigen's operator== asserts on a size mismatch; states of different sizes are just unequal.
template <class A, class B>
bool same(const A& a, const B& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

bool authors_realisation(const CmaEsParams& p) {
  return p.population_size < 2 && p.small_population == CmaSmallPopulation::kAuthors;
}

CmaEsStrategy make_strategy(const CmaEsParams& p) {
  CmaEsStrategy s = cma_strategy(p);
  if (p.eigen_gap == CmaEigenGap::kPurecma) {
    // purecma's gap, 0.5 n lambda / (c1 + c_mu) / n^2, from the rates of floor(lambda / 2)
    // parents weighted ln(mu + 1/2) - ln i, whatever the parents of each update.
    CmaEsStrategy half = s;
    half.mu = std::max(1, s.lambda / 2);
    cma_set_weights_and_rates(half, std::log(half.mu + 0.5));
    s.eigen_interval = 0.5 * static_cast<double>(s.lambda) / ((half.c1 + half.c_mu) * static_cast<double>(s.n));
  }
  return s;
}

}  // namespace

std::string to_string(CmaBoundsHandling value) {
  return std::string(enum_to_string(kCmaBoundsHandlingNames, value));
}

CmaBoundsHandling cma_bounds_handling_from_string(std::string_view text) {
  return enum_from_string(kCmaBoundsHandlingNames, "CMA-ES bounds handling", text);
}

std::string to_string(CmaSmallPopulation value) {
  return std::string(enum_to_string(kCmaSmallPopulationNames, value));
}

CmaSmallPopulation cma_small_population_from_string(std::string_view text) {
  return enum_from_string(kCmaSmallPopulationNames, "CMA-ES small population", text);
}

std::string to_string(CmaEigenGap value) { return std::string(enum_to_string(kCmaEigenGapNames, value)); }

CmaEigenGap cma_eigen_gap_from_string(std::string_view text) {
  return enum_from_string(kCmaEigenGapNames, "CMA-ES eigen gap", text);
}

std::string to_string(CmaRankOne value) { return std::string(enum_to_string(kCmaRankOneNames, value)); }

CmaRankOne cma_rank_one_from_string(std::string_view text) {
  return enum_from_string(kCmaRankOneNames, "CMA-ES rank-one term", text);
}

std::string to_string(CmaObjective value) { return std::string(enum_to_string(kCmaObjectiveNames, value)); }

CmaObjective cma_objective_from_string(std::string_view text) {
  return enum_from_string(kCmaObjectiveNames, "CMA-ES objective", text);
}

void CmaEsParams::validate() const {
  require_at_least("CmaEsParams.dimension", dimension, 1);
  require_at_least("CmaEsParams.population_size", population_size, 1);
  if (!std::isfinite(initial_sigma) || initial_sigma <= 0.0) {
    invalid_param("initial_sigma", initial_sigma, "must be finite and > 0");
  }
  if (!std::isfinite(initial_mean)) invalid_param("initial_mean", initial_mean, "must be finite");
  if (!x0.empty() && x0.size() != static_cast<std::size_t>(dimension)) {
    invalid_param("x0", fmt::format("a vector of size {}", x0.size()),
                  fmt::format("must be empty or have dimension = {} entries", dimension));
  }
  for (std::size_t i = 0; i < x0.size(); ++i) {
    if (!std::isfinite(x0[i])) invalid_param(fmt::format("x0[{}]", i), x0[i], "must be finite");
  }
  if (enum_to_string(kCmaBoundsHandlingNames, bounds) == "?") {
    invalid_param("bounds", static_cast<int>(bounds), "must be one of none, clamp, resample");
  }
  require_at_least("CmaEsParams.max_resample_attempts", max_resample_attempts, 1);
  if (enum_to_string(kCmaSmallPopulationNames, small_population) == "?") {
    invalid_param("small_population", static_cast<int>(small_population), "must be one of one-one, authors");
  }
  if (enum_to_string(kCmaEigenGapNames, eigen_gap) == "?") {
    invalid_param("eigen_gap", static_cast<int>(eigen_gap), "must be one of tutorial, purecma");
  }
  if (enum_to_string(kCmaRankOneNames, rank_one) == "?") {
    invalid_param("rank_one", static_cast<int>(rank_one), "must be one of tutorial, pyribs");
  }
  if (bounds == CmaBoundsHandling::kNone) return;
  if (!std::isfinite(lower_bound)) invalid_param("lower_bound", lower_bound, "must be finite");
  if (!std::isfinite(upper_bound) || upper_bound <= lower_bound) {
    invalid_param("upper_bound", upper_bound, fmt::format("must be finite and > lower_bound = {}", lower_bound));
  }
  const auto check_inside = [&](std::string_view field, double value) {
    if (value < lower_bound || value > upper_bound) {
      invalid_param(field, value,
                    fmt::format("must lie in [lower_bound, upper_bound] = [{}, {}] when bounds = {}",
                                lower_bound, upper_bound, to_string(bounds)));
    }
  };
  if (x0.empty()) check_inside("initial_mean", initial_mean);
  for (std::size_t i = 0; i < x0.size(); ++i) check_inside(fmt::format("x0[{}]", i), x0[i]);
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
  s.samples = Eigen::MatrixXd::Zero(n, sampled_population(params));
  return s;
}

int CmaEs::sampled_population(const CmaEsParams& params) {
  if (!authors_realisation(params)) return params.population_size;
  // c-cmaes's default population (its readpara_SupplementDefaults), with the same int cast.
  return 4 + static_cast<int>(3.0 * std::log(static_cast<double>(params.dimension)));
}

CmaEs::CmaEs(CmaEsParams params) : params_(std::move(params)) {
  params_.validate();
  strategy_ = make_strategy(params_);
  state_ = initial_state(params_);
  initial_ = state_;
  z_.resize(params_.dimension, strategy_.lambda);
  y_.resize(params_.dimension, strategy_.lambda);  // tell_ranked may take every candidate as a parent
  order_.resize(static_cast<std::size_t>(strategy_.lambda));
}

// Draws the normals column by column (the order every source sees), scales them by D, and maps
// them through B, sigma and the mean of the distribution in force.
template <class FillNormals>
const Eigen::MatrixXd& CmaEs::ask_with(FillNormals&& fill_normals) {
  if (state_.awaiting_tell) {
    throw InputError(fmt::format("CmaEs::ask: called twice without tell; tell the fitness of the {} pending "
                                 "candidates first",
                                 strategy_.evaluated));
  }
  const int n = params_.dimension;
  const int lambda = strategy_.lambda;
  // Bounds apply to the candidates that are evaluated: the authors' EA clamped only those.
  const int bounded = strategy_.evaluated;
  const CmaEsState& dist = params_.frozen ? initial_ : state_;
  state_.samples.resize(n, lambda);
  const auto sample_columns = [&](int first, int count) {
    fill_normals(&z_(0, first), Eigen::Index{n} * count);
    for (int k = first; k < first + count; ++k) {
      double* z = &z_(0, k);
      for (int i = 0; i < n; ++i) z[i] *= dist.D(i);
    }
    multiply_columns(dist.B, &z_(0, first), &state_.samples(0, first), count);  // x = m + sigma B D z
    for (int k = first; k < first + count; ++k) {
      double* x = &state_.samples(0, k);
      for (int i = 0; i < n; ++i) x[i] = dist.mean(i) + dist.sigma * x[i];
    }
  };
  cma_sample_within_bounds(params_, state_.samples, bounded, sample_columns);
  state_.awaiting_tell = true;
  return state_.samples;
}

const Eigen::MatrixXd& CmaEs::ask(Rng& rng) { return ask_with(cma_rng_normals(rng)); }

const Eigen::MatrixXd& CmaEs::ask(const std::function<double()>& standard_normal) {
  return ask_with(cma_source_normals("CmaEs", standard_normal));
}

void CmaEs::tell(const Eigen::VectorXd& fitness, CmaObjective objective) {
  const int lambda = strategy_.lambda;
  cma_check_tell("CmaEs", state_.awaiting_tell, fitness, strategy_.evaluated, objective);
  state_.awaiting_tell = false;
  state_.generation += 1;
  state_.evaluations += lambda;
  if (params_.frozen) return;

  rank(fitness, objective);
  update(strategy_);
}

void CmaEs::tell_ranked(std::span<const int> order, int parents) {
  const int lambda = strategy_.lambda;
  if (!state_.awaiting_tell) {
    throw InputError("CmaEs::tell_ranked: called without a pending ask; call ask() first");
  }
  if (strategy_.library_ranking) {
    throw InputError("CmaEs::tell_ranked: not available with small_population = authors; use tell()");
  }
  cma_check_ranked("CmaEs", order, lambda, parents);
  state_.awaiting_tell = false;
  state_.generation += 1;
  state_.evaluations += lambda;
  if (params_.frozen || parents == 0) return;
  std::copy(order.begin(), order.end(), order_.begin());
  CmaEsStrategy s = strategy_;
  s.mu = parents;
  cma_set_weights_and_rates(s, std::log(parents + 0.5));
  if (params_.eigen_gap == CmaEigenGap::kPurecma) s.eigen_interval = strategy_.eigen_interval;
  update(s);
}

void CmaEs::update(const CmaEsStrategy& s) {
  CmaEsState& st = state_;
  const int n = s.n;
  // Steps of the mu best, recomputed from the returned (possibly clamped) points.
  for (int k = 0; k < s.mu; ++k) {
    const double* x = &st.samples(0, order_[static_cast<std::size_t>(k)]);
    double* y = &y_(0, k);
    for (int i = 0; i < n; ++i) y[i] = (x[i] - st.mean(i)) / st.sigma;
  }
  Eigen::VectorXd y_w = Eigen::VectorXd::Zero(n);  // sum of w_k y_k, in k order
  for (int k = 0; k < s.mu; ++k) {
    const double* y = &y_(0, k);
    for (int i = 0; i < n; ++i) y_w(i) += s.weights(k) * y[i];
  }
  for (int i = 0; i < n; ++i) st.mean(i) += st.sigma * y_w(i);  // c_m = 1

  // Cumulative step-size adaptation with C^{-1/2} = B D^{-1} B^T from the last decomposition.
  Eigen::VectorXd rotated(n);
  multiply_transposed(st.B, y_w.data(), rotated.data());
  for (int i = 0; i < n; ++i) rotated(i) /= st.D(i);
  Eigen::VectorXd c_inv_sqrt_y_w(n);
  multiply(st.B, rotated.data(), c_inv_sqrt_y_w.data());
  const double sigma_path_scale = std::sqrt(s.c_sigma * (2.0 - s.c_sigma) * s.mu_eff);
  for (int i = 0; i < n; ++i) {
    st.p_sigma(i) = (1.0 - s.c_sigma) * st.p_sigma(i) + sigma_path_scale * c_inv_sqrt_y_w(i);
  }
  const double p_sigma_norm = std::sqrt(cma_sum_of_squares(st.p_sigma));
  const double dn = n;
  const double path_bias =
      std::sqrt(1.0 - std::pow(1.0 - s.c_sigma, 2.0 * static_cast<double>(st.generation)));
  const bool h_sigma = p_sigma_norm / path_bias < (1.4 + 2.0 / (dn + 1.0)) * s.chi_n;
  const double c_path_scale = h_sigma ? std::sqrt(s.c_c * (2.0 - s.c_c) * s.mu_eff) : 0.0;
  const bool pyribs_rank_one = params_.rank_one == CmaRankOne::kPyribs;
  if (pyribs_rank_one) {
    for (int i = 0; i < n; ++i) st.p_c(i) = (1.0 - s.c_c) * st.p_c(i) + c_path_scale * (st.sigma * y_w(i));
  } else {
    for (int i = 0; i < n; ++i) st.p_c(i) = (1.0 - s.c_c) * st.p_c(i) + c_path_scale * y_w(i);
  }
  const double rank_one_rate = pyribs_rank_one ? s.c1 * s.c1 : s.c1;

  // Rank-one + rank-mu update (the weights sum to 1) on the lower triangle, then mirrored:
  // C_ij = decay C_ij + c1 p_c,i p_c,j + c_mu sum_k w_k y_k,i y_k,j, the sum in k order.
  const double delta_h = h_sigma ? 0.0 : s.c_c * (2.0 - s.c_c);
  const double decay = 1.0 - s.c1 - s.c_mu + s.c1 * delta_h;
  // The k sums run for a whole column of C at once (contiguous in y_'s columns), each entry's
  // still in k order from 0.
  Eigen::VectorXd rank_mu(n);
  for (int j = 0; j < n; ++j) {
    std::fill(rank_mu.data() + j, rank_mu.data() + n, 0.0);
    for (int k = 0; k < s.mu; ++k) {
      const double* y = &y_(0, k);
      const double w = s.weights(k);
      const double y_j = y[j];
      for (int i = j; i < n; ++i) rank_mu(i) += w * (y[i] * y_j);
    }
    for (int i = j; i < n; ++i) {
      st.C(i, j) = decay * st.C(i, j) + rank_one_rate * (st.p_c(i) * st.p_c(j)) + s.c_mu * rank_mu(i);
    }
  }
  for (int j = 1; j < n; ++j) {
    for (int i = 0; i < j; ++i) st.C(i, j) = st.C(j, i);
  }

  st.sigma *= std::exp((s.c_sigma / s.d_sigma) * (p_sigma_norm / s.chi_n - 1.0));

  if (static_cast<double>(st.evaluations - st.eigen_evaluations) > s.eigen_interval) decompose();
}

void CmaEs::rank(const Eigen::VectorXd& fitness, CmaObjective objective) {
  if (!strategy_.library_ranking) {
    cma_rank(order_, fitness, objective);
    return;
  }
  // The authors' realisation: the library minimised the negated meta-fitness of the evaluated
  // candidates, and the unevaluated ones kept its initial value 0. Its index sort inserts each
  // candidate before every earlier one that is not strictly smaller, so equal values end up
  // latest first (the 19 unevaluated candidates of K = 222 rank 19, 18, ..., 1).
  std::vector<double> value(order_.size(), 0.0);
  for (Eigen::Index i = 0; i < fitness.size(); ++i) {
    value[static_cast<std::size_t>(i)] = objective == CmaObjective::kMinimise ? fitness(i) : -fitness(i);
  }
  for (std::size_t i = 0; i < order_.size(); ++i) {
    std::size_t j = i;
    for (; j > 0 && !(value[static_cast<std::size_t>(order_[j - 1])] < value[i]); --j) order_[j] = order_[j - 1];
    order_[j] = static_cast<int>(i);
  }
}

void CmaEs::decompose() {
  SymmetricEigen eigen;
  try {
    eigen = symmetric_eigen(state_.C);
  } catch (const std::exception& e) {
    throw Error(fmt::format("CmaEs: eigendecomposition of the covariance matrix failed at generation {}: {}",
                            state_.generation, e.what()));
  }
  // Rounding can push tiny eigenvalues to or below zero; keep C^{-1/2} finite. The values are
  // ascending, so the last is the largest.
  const Eigen::Index n = eigen.values.size();
  const double floor = std::max(eigen.values(n - 1), 1e-300) * 1e-20;
  for (Eigen::Index i = 0; i < n; ++i) state_.D(i) = std::sqrt(std::max(eigen.values(i), floor));
  state_.B = std::move(eigen.vectors);
  state_.eigen_evaluations = state_.evaluations;
  state_.decompositions += 1;
}

void CmaEs::set_state(const CmaEsState& state) {
  const Eigen::Index n = params_.dimension;
  const Eigen::Index lambda = strategy_.lambda;
  const auto check_vector = [&](const char* name, const Eigen::VectorXd& v) {
    if (v.size() != n) {
      invalid_state(fmt::format("{} has size {}, expected dimension {}", name, v.size(), n));
    }
  };
  const auto check_square = [&](const char* name, const Eigen::MatrixXd& m) {
    if (m.rows() != n || m.cols() != n) {
      invalid_state(fmt::format("{} is {}, expected {}", name, shape(m.rows(), m.cols()), shape(n, n)));
    }
  };
  check_vector("mean", state.mean);
  check_vector("D", state.D);
  check_vector("p_sigma", state.p_sigma);
  check_vector("p_c", state.p_c);
  check_square("C", state.C);
  check_square("B", state.B);
  if (!std::isfinite(state.sigma) || state.sigma <= 0.0) {
    invalid_state(fmt::format("sigma = {}, expected finite and > 0", state.sigma));
  }
  if (!(state.D.array() > 0.0).all()) invalid_state("D has entries <= 0, expected all > 0");
  if (state.generation < 0 || state.evaluations < 0 || state.eigen_evaluations < 0 ||
      state.decompositions < 0 || state.eigen_evaluations > state.evaluations) {
    invalid_state("counters are inconsistent (negative, or eigen_evaluations > evaluations)");
  }
  const bool sized = state.samples.rows() == n && state.samples.cols() == lambda;
  if ((state.awaiting_tell || state.samples.size() != 0) && !sized) {
    invalid_state(fmt::format("samples is {}, expected {}", shape(state.samples.rows(), state.samples.cols()),
                              shape(n, lambda)));
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
