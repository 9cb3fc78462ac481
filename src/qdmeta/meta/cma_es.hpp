#pragma once
// Ask/tell (mu/mu_W, lambda)-CMA-ES with full covariance, following Hansen's tutorial
// ("The CMA Evolution Strategy: A Tutorial", arXiv:1604.00772) with positive recombination
// weights only. QD-Meta uses it to search meta-genotypes (feature-map weights).
//
// Usage:
//   qdmeta::CmaEs cma(params);                    // params.validate() is called
//   const Eigen::MatrixXd& x = cma.ask(rng);      // qdmeta::Rng: n x lambda, one candidate per column
//   cma.tell(fitness, qdmeta::CmaObjective::kMaximise);
//
// The protocol is checked: tell() without a pending ask(), ask() twice in a row, a fitness
// vector of the wrong size or a NaN fitness throw qdmeta::InputError. The whole algorithm state
// is the plain struct CmaEsState (state()/set_state() for checkpoints); the object itself holds
// only the params, the constant strategy parameters and scratch buffers.
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {

// What ask() does with a candidate that falls outside [lower_bound, upper_bound].
enum class CmaBoundsHandling {
  kNone,      // unbounded: the bounds are ignored
  kClamp,     // clamp each coordinate; the clamped point is returned and used in the update
  kResample,  // redraw the candidate (up to max_resample_attempts times), then clamp
};
inline constexpr EnumNames<CmaBoundsHandling, 3> kCmaBoundsHandlingNames{{{CmaBoundsHandling::kNone, "none"},
                                                                      {CmaBoundsHandling::kClamp, "clamp"},
                                                                      {CmaBoundsHandling::kResample, "resample"}}};
std::string to_string(CmaBoundsHandling value);
// Accepts "none", "clamp", "resample"; anything else throws InputError listing those.
CmaBoundsHandling cma_bounds_handling_from_string(std::string_view text);

// How a population_size below 2 is run.
enum class CmaSmallPopulation {
  kOneOne,   // a (1,1)-ES: the one candidate takes weight 1
  // As the authors' C CMA-ES (Hansen's c-cmaes) ran it: the library replaced lambda < 2 by its
  // default 4 + floor(3 ln n) and recombined mu = lambda / 2 samples with weights
  // ln(mu + 1) - ln i, while their EA evaluated (and clamped) only the first population_size
  // samples; the rest kept the library's initial fitness 0 (in minimisation terms). ask() then
  // returns all the samples and tell() takes the population_size evaluated fitness values.
  kAuthors,
};
inline constexpr EnumNames<CmaSmallPopulation, 2> kCmaSmallPopulationNames{
    {{CmaSmallPopulation::kOneOne, "one-one"}, {CmaSmallPopulation::kAuthors, "authors"}}};
std::string to_string(CmaSmallPopulation value);
// Accepts "one-one", "authors"; anything else throws InputError listing those.
CmaSmallPopulation cma_small_population_from_string(std::string_view text);

// How many evaluations CMA-ES lets pass between eigendecompositions of C (sampling and the
// step-size path use the B and D of the last one): a decomposition costs O(n^3), the rest of a
// generation O(n^2 lambda).
enum class CmaEigenGap {
  // More than lambda / ((c1 + c_mu) n 10), c1 and c_mu those of the update just made (the
  // tutorial's "every lambda / (c1 + c_mu) / n / 10 generations" read in evaluations); QD-Meta's.
  kTutorial,
  // More than lambda / (2 (c1 + c_mu) n), c1 and c_mu those of floor(lambda / 2) parents, fixed
  // for the run: Hansen's purecma and pyribs's CMA-ES; 5x lazier. The emitters' default.
  kPurecma,
};
inline constexpr EnumNames<CmaEigenGap, 2> kCmaEigenGapNames{
    {{CmaEigenGap::kTutorial, "tutorial"}, {CmaEigenGap::kPurecma, "purecma"}}};
std::string to_string(CmaEigenGap value);
// Accepts "tutorial", "purecma"; anything else throws InputError listing those.
CmaEigenGap cma_eigen_gap_from_string(std::string_view text);

// CMA-ES's rank-one covariance term.
enum class CmaRankOne {
  kTutorial,  // c1 p_c p_c^T, p_c accumulating the normalised mean steps y_w (the tutorial's)
  // pyribs 0.12's (emitters/opt/_cma_es.py): p_c accumulates the mean's steps sigma y_w, and the
  // term is c1^2 p_c p_c^T, not divided by sigma^2; next to c_mu's term it is nearly nothing. For
  // comparisons with pyribs only (docs/fidelity.md, "Emitters against pyribs").
  kPyribs,
};
inline constexpr EnumNames<CmaRankOne, 2> kCmaRankOneNames{
    {{CmaRankOne::kTutorial, "tutorial"}, {CmaRankOne::kPyribs, "pyribs"}}};
std::string to_string(CmaRankOne value);
// Accepts "tutorial", "pyribs"; anything else throws InputError listing those.
CmaRankOne cma_rank_one_from_string(std::string_view text);

// Whether tell() receives values to minimise or to maximise (QD-Meta maximises meta-fitness).
enum class CmaObjective { kMinimise, kMaximise };
inline constexpr EnumNames<CmaObjective, 2> kCmaObjectiveNames{
    {{CmaObjective::kMinimise, "minimise"}, {CmaObjective::kMaximise, "maximise"}}};
std::string to_string(CmaObjective value);
// Accepts "minimise", "maximise"; anything else throws InputError listing those.
CmaObjective cma_objective_from_string(std::string_view text);

struct CmaEsParams {
  int dimension = 0;                 // n, number of search variables (required, >= 1)
  int population_size = 10;          // lambda, candidates per ask (>= 1); mu = max(1, lambda / 2)
  double initial_sigma = 2.0 / 3.0;  // sigma0, initial step size (> 0; range / 3 for [-1, 1])
  double initial_mean = 0.0;         // every coordinate of the initial mean (unless x0 is set)
  std::vector<double> x0;            // optional initial mean; if non-empty its size is n
  double lower_bound = -1.0;         // lower bound of every coordinate (unused with kNone)
  double upper_bound = 1.0;          // upper bound of every coordinate (unused with kNone)
  CmaBoundsHandling bounds = CmaBoundsHandling::kClamp;  // what to do outside the bounds
  int max_resample_attempts = 100;   // kResample: draws per candidate before clamping (>= 1)
  bool frozen = false;  // ablation control: always sample the initial distribution, never update
  CmaSmallPopulation small_population = CmaSmallPopulation::kOneOne;  // population_size 1 only
  CmaEigenGap eigen_gap = CmaEigenGap::kTutorial;  // how often C is decomposed
  CmaRankOne rank_one = CmaRankOne::kTutorial;      // the rank-one term of C's update

  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
};

// Constants derived from (n, lambda) once, as in the tutorial's Table 1 (positive weights).
struct CmaEsStrategy {
  int n = 0;                  // dimension
  int lambda = 0;             // samples per ask (population_size unless the authors' realisation)
  int evaluated = 0;          // fitness values per tell (population_size)
  bool library_ranking = false;  // the authors' realisation: c-cmaes's ranking, unevaluated = 0
  int mu = 0;                 // parents, floor(lambda / 2)
  Eigen::VectorXd weights;    // w_i proportional to ln((lambda + 1) / 2) - ln i (c-cmaes: ln(mu + 1) - ln i), sum 1
  double mu_eff = 0.0;        // 1 / sum w_i^2
  double c_sigma = 0.0;       // step-size path learning rate
  double d_sigma = 0.0;       // step-size damping
  double c_c = 0.0;           // covariance path learning rate
  double c1 = 0.0;            // rank-one learning rate
  double c_mu = 0.0;          // rank-mu learning rate
  double chi_n = 0.0;         // E||N(0, I)||
  double eigen_interval = 0.0;  // decompose C only after more than this many evaluations
};

// The complete mutable state; copy it to checkpoint, compare it with ==.
struct CmaEsState {
  Eigen::VectorXd mean;     // m, distribution mean (n)
  double sigma = 0.0;       // step size
  Eigen::MatrixXd C;        // covariance (n x n)
  Eigen::MatrixXd B;        // eigenvectors of C at the last decomposition (columns)
  Eigen::VectorXd D;        // square roots of the eigenvalues at the last decomposition
  Eigen::VectorXd p_sigma;  // conjugate evolution path
  Eigen::VectorXd p_c;      // evolution path
  std::int64_t generation = 0;          // completed tell() calls
  std::int64_t evaluations = 0;         // fitness values received
  std::int64_t eigen_evaluations = 0;   // value of `evaluations` at the last decomposition
  std::int64_t decompositions = 0;      // eigendecompositions of C performed
  bool awaiting_tell = false;           // ask() returned candidates that tell() has not seen
  Eigen::MatrixXd samples;              // the pending candidates (n x lambda), as returned

  friend bool operator==(const CmaEsState& a, const CmaEsState& b);
};

class CmaEs {
 public:
  explicit CmaEs(CmaEsParams params);

  // Samples lambda candidates (columns of an n x lambda matrix; lambda = strategy().lambda) from N(m, sigma^2 C), with
  // bounds handling applied, drawing the n x lambda standard normals from rng.normal() in one
  // pass (column by column; with kResample one column at a time, as each may be redrawn). The
  // reference stays valid until the next ask() or set_state().
  const Eigen::MatrixXd& ask(Rng& rng);

  // The same from any source of independent N(0, 1) draws, one call per draw, in the same order:
  // ask([&rng] { return rng.normal(); }) gives the same bits as ask(rng).
  const Eigen::MatrixXd& ask(const std::function<double()>& standard_normal);

  // Convenience: draws the normals from another UniformRandomBitGenerator through
  // std::normal_distribution (so the exact sequence depends on the standard library).
  template <class Urbg>
  const Eigen::MatrixXd& ask(Urbg& urbg) {
    std::normal_distribution<double> normal(0.0, 1.0);
    return ask(std::function<double()>([&urbg, &normal] { return normal(urbg); }));
  }

  // Updates the distribution from the fitness of the pending candidates, in ask() order: the
  // first strategy().evaluated of them (all but in the authors' realisation of lambda = 1).
  void tell(const Eigen::VectorXd& fitness, CmaObjective objective);

  // Updates from the caller's ranking of the pending candidates (`order`: their indices, best
  // first, a permutation of 0..lambda-1) with the first `parents` of them as parents, weighted
  // ln(parents + 1/2) - ln i and with the learning rates recomputed for that many, as the
  // emitters of CMA-ME need (emitters/evolution_strategy_emitter.hpp: parents may be the
  // candidates an archive took). parents = 0 closes the pending ask without an update. Refused
  // (InputError) under the authors' small-population realisation.
  void tell_ranked(std::span<const int> order, int parents);

  const CmaEsParams& params() const { return params_; }
  const CmaEsStrategy& strategy() const { return strategy_; }
  const CmaEsState& state() const { return state_; }
  // Replaces the state (e.g. from a checkpoint); throws InputError if its sizes do not match
  // the params or it is not a valid state (non-positive sigma, pending flag without samples).
  void set_state(const CmaEsState& state);

  // Checkpoints: the whole state. load() checks it as set_state() does.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

  // The state of a freshly constructed optimiser for these params.
  static CmaEsState initial_state(const CmaEsParams& params);
  // Candidates per ask() for these params: population_size, or c-cmaes's default
  // 4 + floor(3 ln n) where the authors' realisation replaces a population_size below 2.
  static int sampled_population(const CmaEsParams& params);

 private:
  // fill_normals(double* out, Eigen::Index count) writes `count` independent N(0, 1) draws.
  template <class FillNormals>
  const Eigen::MatrixXd& ask_with(FillNormals&& fill_normals);
  void decompose();
  // The update of the mean, paths, covariance and step size from the parents order_[0..s.mu).
  void update(const CmaEsStrategy& s);
  // Fills order_ with the candidates best first.
  void rank(const Eigen::VectorXd& fitness, CmaObjective objective);

  CmaEsParams params_;
  CmaEsStrategy strategy_;
  CmaEsState state_;
  CmaEsState initial_;  // the frozen control samples from this distribution forever
  // Scratch buffers, not state.
  Eigen::MatrixXd z_;  // standard normals scaled by D, n x lambda
  Eigen::MatrixXd y_;
  std::vector<int> order_;
};

}  // namespace qdmeta
