#include "qdmeta/emitters/cell_thresholds.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

std::string to_string(AddMode value) { return std::string(enum_to_string(kAddModeNames, value)); }

void ThresholdParams::validate() const {
  require(kLearningRate, alpha);
  if (threshold_min == -std::numeric_limits<double>::infinity() && alpha == 1.0) return;  // CMA-ME's
  try {
    require(kThresholdMin, threshold_min);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}, or -inf with learning_rate = 1 (CMA-ME's)", e.what()));
  }
}

CellThresholds::CellThresholds(Index cells, ThresholdParams params) : params_(params) {
  params_.validate();
  require_at_least("CellThresholds cells", cells, Index{1});
  thresholds_.assign(static_cast<std::size_t>(cells), params_.threshold_min);
  reached_.assign(static_cast<std::size_t>(cells), 0);
}

ThresholdOutcome CellThresholds::offer(Index cell, double objective) {
  if (cell < 0 || cell >= cells()) {
    throw InputError(fmt::format("CellThresholds::offer: cell = {} is outside [0, {})", cell, cells()));
  }
  if (!std::isfinite(objective)) {
    throw InputError(fmt::format("CellThresholds::offer: objective = {} is invalid: must be finite", objective));
  }
  const auto e = static_cast<std::size_t>(cell);
  double& t = thresholds_[e];
  ThresholdOutcome outcome;
  // An unreached cell under -inf scores against 0, so that its value stays finite.
  outcome.improvement = objective - (std::isinf(t) ? 0.0 : t);
  if (!(objective > t)) return outcome;
  outcome.status = reached_[e] ? AddStatus::kImproved : AddStatus::kNew;
  reached_[e] = 1;
  // alpha = 1 sets t_e = f exactly (and never forms 0 * -inf). The multiply-add is written out
  // (core/fused.hpp), so that the compiler's contraction does not decide its rounding.
  t = params_.alpha == 1.0 ? objective : fused(params_.alpha, objective, (1.0 - params_.alpha) * t);
  return outcome;
}

void CellThresholds::offer_batch(std::span<const Index> cells, std::span<const Real> objectives,
                                 std::span<const std::uint8_t> valid, std::span<ThresholdOutcome> outcomes) {
  const std::size_t rows = cells.size();
  if (objectives.size() != rows || outcomes.size() != rows || (!valid.empty() && valid.size() != rows)) {
    throw InputError(fmt::format("CellThresholds::offer_batch: {} cells, {} objectives, {} valid flags and {} outcome "
                                 "slots: give one of each per row",
                                 rows, objectives.size(), valid.size(), outcomes.size()));
  }
  const auto is_valid = [&](std::size_t r) { return valid.empty() || valid[r] != 0; };
  for (std::size_t r = 0; r < rows; ++r) {
    if (!is_valid(r)) continue;
    if (cells[r] < 0 || cells[r] >= this->cells())
      throw InputError(fmt::format("CellThresholds::offer_batch: cells[{}] = {} is outside [0, {})", r, cells[r], this->cells()));
    if (!std::isfinite(objectives[r]))
      throw InputError(fmt::format("CellThresholds::offer_batch: objectives[{}] = {} is invalid: must be finite", r,
                                   objectives[r]));
  }
  // Every row against the thresholds before the batch; the accepted ones, by (cell, row).
  std::vector<std::pair<Index, std::size_t>> accepted;
  for (std::size_t r = 0; r < rows; ++r) {
    ThresholdOutcome& outcome = outcomes[r];
    if (!is_valid(r)) {
      outcome = {AddStatus::kNotAdded, -std::numeric_limits<double>::infinity()};
      continue;
    }
    const auto e = static_cast<std::size_t>(cells[r]);
    const double f = objectives[r], t = thresholds_[e];
    outcome = {AddStatus::kNotAdded, f - (std::isinf(t) ? 0.0 : t)};
    if (!(f > t)) continue;
    outcome.status = reached_[e] ? AddStatus::kImproved : AddStatus::kNew;
    accepted.emplace_back(cells[r], r);
  }
  std::sort(accepted.begin(), accepted.end());
  // Each cell's accepted rows move its threshold once; their objectives are summed in row order.
  // This file is compiled with -ffp-contract=off: the update rounds as written, product by product.
  for (std::size_t first = 0; first < accepted.size();) {
    const Index cell = accepted[first].first;
    std::size_t last = first;
    double sum = 0.0, best = -std::numeric_limits<double>::infinity();
    for (; last < accepted.size() && accepted[last].first == cell; ++last) {
      const double f = objectives[accepted[last].second];
      sum += f;
      best = std::max(best, f);
    }
    const auto e = static_cast<std::size_t>(cell);
    const auto k = static_cast<double>(last - first);
    if (std::isinf(params_.threshold_min)) {
      thresholds_[e] = best;  // alpha = 1 (validate()): the threshold is the cell's best objective
    } else {
      const double keep = std::pow(1.0 - params_.alpha, k);  // (1 - alpha)^k
      thresholds_[e] = keep * thresholds_[e] + (sum / k) * (1.0 - keep);
    }
    reached_[e] = 1;
    first = last;
  }
}

void CellThresholds::raise_to(Index cell, double objective) {
  if (cell < 0 || cell >= cells()) {
    throw InputError(fmt::format("CellThresholds::raise_to: cell = {} is outside [0, {})", cell, cells()));
  }
  const auto e = static_cast<std::size_t>(cell);
  if (!(objective > thresholds_[e])) return;
  thresholds_[e] = objective;
  reached_[e] = 1;
}

void CellThresholds::clear() {
  std::fill(thresholds_.begin(), thresholds_.end(), params_.threshold_min);
  std::fill(reached_.begin(), reached_.end(), std::uint8_t{0});
}

void CellThresholds::save(BinaryWriter& out) const {
  out.tag("cell thresholds");
  out.value(params_.alpha);
  out.value(params_.threshold_min);
  out.values(thresholds_);
  out.values(reached_);
}

void CellThresholds::load(BinaryReader& in) {
  in.expect_tag("cell thresholds");
  const double alpha = in.value<double>("threshold alpha");
  const double threshold_min = in.value<double>("threshold_min");
  if (alpha != params_.alpha || threshold_min != params_.threshold_min) {
    throw InputError(fmt::format("CellThresholds::load: the checkpoint has alpha = {}, threshold_min = {}; "
                                 "these thresholds have alpha = {}, threshold_min = {}",
                                 alpha, threshold_min, params_.alpha, params_.threshold_min));
  }
  auto thresholds = in.values<double>("thresholds");
  auto reached = in.values<std::uint8_t>("reached flags");
  if (thresholds.size() != thresholds_.size() || reached.size() != reached_.size()) {
    throw InputError(fmt::format("CellThresholds::load: the checkpoint has {} thresholds and {} flags; expected {}",
                                 thresholds.size(), reached.size(), thresholds_.size()));
  }
  thresholds_ = std::move(thresholds);
  reached_ = std::move(reached);
}

}  // namespace qdmeta
