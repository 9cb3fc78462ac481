#include "qdmeta/emitters/cell_thresholds.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

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
