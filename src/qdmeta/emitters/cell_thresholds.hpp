#pragma once
// CMA-MAE's acceptance thresholds (Fontaine & Nikolaidis 2023, "Covariance Matrix Adaptation
// MAP-Annealing", Algorithm 1): one threshold t_e per cell of an archive, kept beside it. A
// candidate of objective f in cell e is accepted when f > t_e, its improvement value is
// f - t_e, and acceptance anneals the threshold, t_e <- (1 - alpha) t_e + alpha f. A cell never
// reached has t_e = threshold_min. alpha = 1 with threshold_min = -inf is CMA-ME: t_e is then the
// best objective the cell has seen, and acceptance is MAP-Elites's.
//
// Offers are applied one at a time, in order, as Algorithm 1 does; pyribs instead scores a whole
// batch against the thresholds before it and applies its batch update rule (the two agree on a
// batch with at most one candidate per cell).
#include <cstdint>
#include <limits>
#include <vector>

#include "qdmeta/archive/elite_batch.hpp"  // AddStatus
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/scalars.hpp"

namespace qdmeta {

struct ThresholdParams {
  // archive.learning_rate and archive.threshold_min as "cma-mae" reads them (docs/config.md).
  static constexpr RealParam kLearningRate{
      "archive", "learning_rate", 0.0, 1.0, Open::kNone,
      "cma-mae only (refused for cma-me, whose rate is 1): the threshold learning rate alpha; an accepted candidate "
      "moves its cell's threshold t to (1 - alpha) t + alpha f. At 1, with CMA-ME's ranker and rules and "
      "`threshold_min` below every objective, the run is CMA-ME's bit for bit (tests/cli/cma_mae_cli_test.cpp)"};
  static constexpr RealParam kThresholdMin{"archive", "threshold_min", -kNoUpper, kNoUpper, Open::kNone,
                                           "cma-mae only: the threshold of a cell never reached"};
  double alpha = 1.0;  // threshold learning rate (kLearningRate)
  // The threshold of a cell never reached (kThresholdMin), or -inf (CMA-ME's) with alpha = 1: the
  // annealed mean of -inf and f is not a number.
  double threshold_min = -std::numeric_limits<double>::infinity();
  // Throws InputError naming the field, its value and the rule it breaks.
  void validate() const;
  friend bool operator==(const ThresholdParams& a, const ThresholdParams& b) = default;
};

// What offering one candidate did. kNew: its cell had never accepted a candidate; kImproved: it
// beat the threshold of a reached cell; kNotAdded: it did not beat the threshold.
struct ThresholdOutcome {
  AddStatus status = AddStatus::kNotAdded;
  // f - t_e with t_e before the offer; for a cell never reached under threshold_min = -inf it is
  // f - 0 (as pyribs), which keeps it finite.
  double improvement = 0.0;
};

class CellThresholds {
 public:
  CellThresholds(Index cells, ThresholdParams params);

  const ThresholdParams& params() const { return params_; }
  Index cells() const { return static_cast<Index>(thresholds_.size()); }
  // t_e: threshold_min until the cell accepts a candidate.
  double threshold(Index cell) const { return thresholds_[static_cast<std::size_t>(cell)]; }
  bool reached(Index cell) const { return reached_[static_cast<std::size_t>(cell)] != 0; }

  // Scores a candidate of objective f in `cell` against t_e and anneals t_e when it is accepted.
  // Throws InputError for a cell outside [0, cells) or a non-finite f.
  ThresholdOutcome offer(Index cell, double objective);

  // Every cell back to threshold_min, unreached.
  void clear();

  // A warm start from an elite already in `cell` (QD-Meta's rebuilt maps): t_e becomes
  // `objective` and the cell reached when it beats t_e, as offering it at learning rate 1 would.
  void raise_to(Index cell, double objective);

  // Checkpoints: the params, every threshold and reached flag. load() requires the same cell
  // count and params and throws InputError otherwise.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

  friend bool operator==(const CellThresholds& a, const CellThresholds& b) = default;

 private:
  ThresholdParams params_;
  std::vector<double> thresholds_;
  std::vector<std::uint8_t> reached_;
};

}  // namespace qdmeta
