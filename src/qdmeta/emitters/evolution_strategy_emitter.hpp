#pragma once
// CMA-ME's emitter (Fontaine et al. 2020), as pyribs's EvolutionStrategyEmitter: qdmeta's
// CMA-ES (meta/cma_es.hpp) proposes each batch; told the archive's outcomes, the emitter ranks
// the batch (ranking.hpp), takes the best as parents (all the rows the archive took under the
// "filter" rule, half the batch under "mu") and updates CMA-ES through tell_ranked. It restarts
// CMA-ES from a uniformly drawn elite when its restart rule fires or CMA-ES has converged; the
// draw needs a random stream, so the restart happens at the next ask().
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "qdmeta/emitters/emitter.hpp"
#include "qdmeta/emitters/ranking.hpp"
#include "qdmeta/meta/cma_es.hpp"
#include "qdmeta/meta/sep_cma_es.hpp"

namespace qdmeta {

// How many of the ranked rows become CMA-ES's parents.
enum class EmitterSelection {
  kFilter,  // the rows the archive took (new or improved): mu varies per batch
  kMu,      // the best half, floor(batch_size / 2) (at least 1)
};
inline constexpr EnumNames<EmitterSelection, 2> kEmitterSelectionNames{
    {{EmitterSelection::kFilter, "filter"}, {EmitterSelection::kMu, "mu"}}};
std::string to_string(EmitterSelection value);
EmitterSelection emitter_selection_from_string(std::string_view text);

// When CMA-ES restarts, besides its own convergence (which always restarts it).
enum class EmitterRestart {
  kNoImprovement,  // a batch of which the archive took no row
  kBasic,          // only convergence
  kEveryN,         // every restart_every tells
};
inline constexpr EnumNames<EmitterRestart, 3> kEmitterRestartNames{{{EmitterRestart::kNoImprovement, "no-improvement"},
                                                                    {EmitterRestart::kBasic, "basic"},
                                                                    {EmitterRestart::kEveryN, "every-n"}}};
std::string to_string(EmitterRestart value);
EmitterRestart emitter_restart_from_string(std::string_view text);

// Which evolution strategy proposes the batches (pyribs's es argument).
enum class EvolutionStrategyKind {
  kCmaEs,     // full covariance (meta/cma_es.hpp), pyribs's "cma_es"
  kSepCmaEs,  // diagonal covariance, O(n) per sample (meta/sep_cma_es.hpp), pyribs's "sep_cma_es"
};
inline constexpr EnumNames<EvolutionStrategyKind, 2> kEvolutionStrategyKindNames{
    {{EvolutionStrategyKind::kCmaEs, "cma-es"}, {EvolutionStrategyKind::kSepCmaEs, "sep-cma-es"}}};
std::string to_string(EvolutionStrategyKind value);
EvolutionStrategyKind evolution_strategy_kind_from_string(std::string_view text);

struct EvolutionStrategyEmitterParams {
  std::vector<double> x0;  // the first mean, one value per gene (required)
  static constexpr RealParam kSigma0{"emitters", "sigma0", 0.0, kNoUpper, Open::kLower,
                                     "CMA-ES's step size at the start and at each restart, in gene units (genes are "
                                     "in [0, 1])"};
  static constexpr IntParam kRestartEvery{"emitters", "restart_every", 1, 1'000'000'000,
                                          "every-n only (refused with another rule): steps between restarts"};
  double sigma0 = 0.1;     // CMA-ES's initial step size at the start and at each restart (kSigma0)
  int batch_size = 36;     // rows per ask (CMA-ES's lambda, kEmitterBatchSize)
  EmitterRanker ranker = EmitterRanker::kTwoStageImprovement;
  EmitterSelection selection = EmitterSelection::kFilter;
  EmitterRestart restart = EmitterRestart::kNoImprovement;
  int restart_every = 0;  // kEveryN: tells between restarts (kRestartEvery); unused otherwise
  // Gene bounds, as CMA-ES's (meta/cma_es.hpp); kNone leaves the genes unbounded.
  CmaBoundsHandling bounds = CmaBoundsHandling::kNone;
  double lower_bound = 0.0;
  double upper_bound = 1.0;
  // The random-direction rankers: the extent of each measure (upper - lower bound, > 0). A
  // direction is N(0, I) scaled by these, drawn at the first ask() and at each restart.
  std::vector<double> measure_ranges;
  // How often CMA-ES decomposes its covariance: pyribs's gap by default (meta/cma_es.hpp).
  CmaEigenGap eigen_gap = CmaEigenGap::kPurecma;
  // CMA-ES's rank-one term; "pyribs" reproduces pyribs 0.12's, for comparisons with it only.
  CmaRankOne rank_one = CmaRankOne::kTutorial;
  // The full CMA-ES or the separable one (which has no eigen_gap and only the tutorial's rank_one).
  EvolutionStrategyKind es = EvolutionStrategyKind::kCmaEs;
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
};

// CMA-ES's convergence as pyribs checks it (after pycma): condition number of C above 1e14, a
// distribution narrower than 1e-11 (sigma sqrt(largest eigenvalue)), or best and worst rank keys
// of the batch within 1e-12 (flat).
bool cma_converged(const CmaEsState& state, const std::vector<RankKey>& ranked_keys);
// The same for the separable CMA-ES, whose axes are the square roots of C's diagonal.
bool cma_converged(const SepCmaEsState& state, const std::vector<RankKey>& ranked_keys);

class EvolutionStrategyEmitter : public BatchEmitter {
 public:
  // `pick_elite` gives a restart's new mean (from x0 when the archive is empty).
  EvolutionStrategyEmitter(EvolutionStrategyEmitterParams params, ElitePicker pick_elite);

  const EvolutionStrategyEmitterParams& params() const { return params_; }
  const RowMatrix& ask(Rng& rng) override;
  void tell(const EmitterResults& results) override;
  // Its tell ranks, updates its own CMA-ES and decomposes C there: a Scheduler's costliest step,
  // run for several emitters at once.
  bool tells_alone() const override { return true; }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

  // The full CMA-ES; InputError when the emitter runs the separable one (es = sep-cma-es).
  const CmaEs& optimiser() const;
  // The separable CMA-ES; InputError when the emitter runs the full one.
  const SepCmaEs& separable_optimiser() const;
  std::int64_t tells() const { return tells_; }
  std::int64_t restarts() const { return restarts_; }
  // True from a tell whose restart rule fired until the next ask() restarts CMA-ES.
  bool restart_pending() const { return restart_pending_; }
  // restarts(), plus the one a fired rule has made due (pyribs counts it at the tell).
  std::int64_t ended_runs() const override { return restarts_ + (restart_pending_ ? 1 : 0); }
  // The parents of the last tell (the "filter" rule's mu when it is the rule).
  int last_parents() const { return last_parents_; }
  // The random-direction rankers' direction in measure space (empty before the first ask()).
  const std::vector<double>& direction() const { return direction_; }

 private:
  void restart(Rng& rng);
  void draw_direction(Rng& rng);

  EvolutionStrategyEmitterParams params_;
  ElitePicker pick_elite_;
  std::variant<CmaEs, SepCmaEs> es_;
  std::int64_t tells_ = 0;
  std::int64_t restarts_ = 0;
  bool restart_pending_ = false;
  int last_parents_ = 0;
  std::vector<double> direction_;
};

}  // namespace qdmeta
