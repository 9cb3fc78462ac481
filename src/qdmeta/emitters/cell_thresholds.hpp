#pragma once
// CMA-MAE's acceptance thresholds (Fontaine & Nikolaidis 2023, "Covariance Matrix Adaptation
// MAP-Annealing", Algorithm 1): one threshold t_e per cell of an archive, kept beside it. A
// candidate of objective f in cell e is accepted when f > t_e, its improvement value is
// f - t_e, and acceptance anneals the threshold, t_e <- (1 - alpha) t_e + alpha f. A cell never
// reached has t_e = threshold_min. alpha = 1 with threshold_min = -inf is CMA-ME: t_e is then the
// best objective the cell has seen, and acceptance is MAP-Elites's.
//
// offer() applies offers one at a time, in order, as Algorithm 1 does (pyribs's add_mode
// "single"); offer_batch() scores a whole batch against the thresholds before it and moves each
// cell's threshold once by the paper's batch update rule (its appendix; pyribs's add_mode
// "batch", the default of its schedulers). The two agree on a batch with at most one accepted
// candidate per cell.
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "qdmeta/archive/elite_batch.hpp"  // AddStatus
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/params.hpp"  // EnumNames, RealParam
#include "qdmeta/core/scalars.hpp"

namespace qdmeta {

// How a scheduler offers a batch to the thresholds: kSingle, one row at a time in order (offer);
// kBatch, every row against the thresholds before the batch (offer_batch). pyribs's add_mode.
enum class AddMode { kSingle, kBatch };
inline constexpr EnumNames<AddMode, 2> kAddModeNames{{{AddMode::kSingle, "single"}, {AddMode::kBatch, "batch"}}};
std::string to_string(AddMode value);

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

  // Scores row r (objective f_r in cells[r]) against t_e as it was before the batch: kNew in a
  // cell never reached, kImproved in a reached one, improvement f_r - t_e either way (f_r - 0
  // in a cell never reached under -inf), so rows sharing a cell share its status rule. Then each
  // cell that k >= 1 rows beat moves once: under threshold_min = -inf to the largest of their
  // objectives (MAP-Elites's rule), otherwise to (1 - alpha)^k t_e + (1 - (1 - alpha)^k) mean(f),
  // the mean of those k objectives (the paper's batch rule: k offers of their mean, one at a
  // time). A row whose `valid` flag is 0 (empty: all valid) enters no cell: kNotAdded,
  // improvement -inf. Throws InputError before anything changes for a cell outside [0, cells),
  // a valid row's non-finite f, or spans of different lengths.
  void offer_batch(std::span<const Index> cells, std::span<const Real> objectives,
                   std::span<const std::uint8_t> valid, std::span<ThresholdOutcome> outcomes);

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
