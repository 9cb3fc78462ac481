#pragma once
// Ask/tell separable CMA-ES (sep-CMA-ES; Ros & Hansen, "A Simple Modification in CMA-ES Achieving
// Linear Time and Space Complexity", PPSN 2008): CMA-ES (cma_es.hpp) with a diagonal covariance.
// Sampling and the update cost O(n lambda) and there is no eigendecomposition, so it suits large
// genotypes (pyribs's es = "sep_cma_es"). Its covariance rates are the full ES's scaled by
// (n + 2) / 3: c1' = c1 (n + 2) / 3, c_mu' = min(1 - c1', c_mu (n + 2) / 3), as the paper's
// c_cov' (and pycma's diagonal mode) does, so a diagonal learns about n / 3 times faster.
//
// The same shape as CmaEs: ask(rng) returns n x lambda candidates, tell() or tell_ranked()
// updates; the state is the plain struct SepCmaEsState (state()/set_state()/save()/load()).
// It takes CmaEsParams: eigen_gap does not apply (never used), and rank_one = pyribs and the
// authors' small-population realisation are refused (they belong to the full ES only).
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/meta/cma_es.hpp"

namespace qdmeta {

// The complete mutable state; copy it to checkpoint, compare it with ==.
struct SepCmaEsState {
  Eigen::VectorXd mean;     // m (n)
  double sigma = 0.0;       // step size
  Eigen::VectorXd C;        // the covariance's diagonal (n), all > 0
  Eigen::VectorXd p_sigma;  // conjugate evolution path
  Eigen::VectorXd p_c;      // evolution path
  std::int64_t generation = 0;   // completed tell() calls
  std::int64_t evaluations = 0;  // candidates told
  bool awaiting_tell = false;    // ask() returned candidates that tell() has not seen
  Eigen::MatrixXd samples;       // the pending candidates (n x lambda), as returned

  friend bool operator==(const SepCmaEsState& a, const SepCmaEsState& b);
};

class SepCmaEs {
 public:
  // Validates the params (InputError naming the field).
  explicit SepCmaEs(CmaEsParams params);

  // lambda candidates x = m + sigma sqrt(C) z, z drawn from rng.normal() column by column, with
  // the bounds handling of the params. Valid until the next ask() or set_state().
  const Eigen::MatrixXd& ask(Rng& rng);
  // The same from any source of N(0, 1) draws, one call per draw in the same order.
  const Eigen::MatrixXd& ask(const std::function<double()>& standard_normal);

  // Updates from the fitness of the pending candidates, in ask() order.
  void tell(const Eigen::VectorXd& fitness, CmaObjective objective);
  // Updates from the caller's order (best first) with the first `parents` as parents, weighted
  // ln(parents + 1/2) - ln i and with the rates for that many (CmaEs::tell_ranked's contract).
  void tell_ranked(std::span<const int> order, int parents);

  const CmaEsParams& params() const { return params_; }
  // The rates in use for floor(lambda / 2) parents (c1 and c_mu already scaled; eigen_interval 0).
  const CmaEsStrategy& strategy() const { return strategy_; }
  const SepCmaEsState& state() const { return state_; }
  // Replaces the state; InputError if its sizes do not match the params or it is not valid.
  void set_state(const SepCmaEsState& state);
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

  static SepCmaEsState initial_state(const CmaEsParams& params);
  // The separable rates for the strategy s of the full ES (same n, mu, weights).
  static void separate_rates(CmaEsStrategy& s);
  // CmaEsParams::validate() and the separable ES's own refusals.
  static void validate(const CmaEsParams& params);

 private:
  template <class FillNormals>
  const Eigen::MatrixXd& ask_with(FillNormals&& fill_normals);
  void update(const CmaEsStrategy& s);

  CmaEsParams params_;
  CmaEsStrategy strategy_;
  SepCmaEsState state_;
  SepCmaEsState initial_;  // what the frozen control samples
  // Scratch buffers, not state.
  Eigen::VectorXd scale_;  // sqrt(C) at ask()
  Eigen::MatrixXd y_;      // the parents' steps (x - m) / sigma
  std::vector<int> order_;
};

}  // namespace qdmeta
