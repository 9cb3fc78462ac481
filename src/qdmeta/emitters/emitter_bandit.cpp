#include "qdmeta/emitters/emitter_bandit.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

BanditReselect bandit_reselect_from_string(std::string_view text) {
  if (text == "terminated") return BanditReselect::kTerminated;
  if (text == "all") return BanditReselect::kAll;
  throw InputError(fmt::format("reselect = '{}' is not 'terminated' or 'all'", text));
}

void BanditParams::validate(std::size_t pool) const {
  if (pool == 0) throw InputError("BanditScheduler emitter pool is empty: give at least one emitter");
  if (num_active < 1 || static_cast<std::size_t>(num_active) > pool) {
    throw InputError(fmt::format("BanditParams.num_active = {} is out of range: must be in [1, {}] (the pool's size)",
                                 num_active, pool));
  }
  if (!std::isfinite(zeta) || zeta < 0.0) {
    throw InputError(fmt::format("BanditParams.zeta = {} is invalid: must be finite and >= 0", zeta));
  }
}

EmitterBandit::EmitterBandit(std::size_t pool, BanditParams params)
    : params_(params), active_(pool, 0), success_(pool, 0.0), selection_(pool, 0.0), runs_seen_(pool, 0) {
  params_.validate(pool);
}

double EmitterBandit::ucb1(std::size_t i) const {
  if (selection_[i] == 0.0) return std::numeric_limits<double>::infinity();
  const double total = std::accumulate(success_.begin(), success_.end(), 0.0);
  if (total == 0.0) return std::numeric_limits<double>::quiet_NaN();
  return success_[i] / selection_[i] + params_.zeta * std::sqrt(std::log(total) / selection_[i]);
}

const std::vector<std::uint8_t>& EmitterBandit::choose(std::span<const std::int64_t> ended_runs) {
  if (ended_runs.size() != active_.size()) {
    throw InputError(fmt::format("EmitterBandit::choose: {} run counts for a pool of {}", ended_runs.size(), pool()));
  }
  std::vector<std::uint8_t> reselect = active_;
  if (params_.reselect == BanditReselect::kTerminated) {
    for (std::size_t i = 0; i < pool(); ++i) {
      reselect[i] = ended_runs[i] < 0 || ended_runs[i] > runs_seen_[i];
      runs_seen_[i] = ended_runs[i];
    }
  }
  // Too few active (the first ask): the first inactive ones of the pool join and stay.
  auto missing = params_.num_active - static_cast<int>(std::count(active_.begin(), active_.end(), 1));
  for (std::size_t i = 0; missing > 0; ++i) {
    reselect[i] = 0;
    if (!active_[i]) {
      active_[i] = 1;
      --missing;
    }
  }
  for (std::size_t i = 0; i < pool(); ++i)
    if (reselect[i]) active_[i] = 0;
  if (std::find(reselect.begin(), reselect.end(), 1) != reselect.end()) fill_by_ucb1();
  return active_;
}

void EmitterBandit::fill_by_ucb1() {
  std::vector<double> value(pool());
  for (std::size_t i = 0; i < pool(); ++i) value[i] = ucb1(i);
  // pyribs sorts its values ascending (numpy's insertion sort on a pool of up to 16: ties, and
  // NaN, which compares false, keep their order) and takes them from the top.
  std::vector<std::size_t> order(pool());
  std::iota(order.begin(), order.end(), std::size_t{0});
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::size_t v = order[k];
    std::size_t j = k;
    for (; j > 0 && value[v] < value[order[j - 1]]; --j) order[j] = order[j - 1];
    order[j] = v;
  }
  auto active = static_cast<int>(std::count(active_.begin(), active_.end(), 1));
  for (auto it = order.rbegin(); it != order.rend() && active < params_.num_active; ++it) {
    if (!active_[*it]) {
      active_[*it] = 1;
      ++active;
    }
  }
}

void EmitterBandit::record(std::size_t i, Index rows, Index successes) {
  selection_[i] += static_cast<double>(rows);
  success_[i] += static_cast<double>(successes);
}

void EmitterBandit::save(BinaryWriter& out) const {
  out.tag("emitter bandit");
  out.value(static_cast<std::int64_t>(params_.num_active));
  out.value(static_cast<std::int64_t>(params_.reselect));
  out.value(params_.zeta);
  out.values(active_);
  out.values(success_);
  out.values(selection_);
  out.values(runs_seen_);
}

void EmitterBandit::load(BinaryReader& in) {
  in.expect_tag("emitter bandit");
  BanditParams saved;
  saved.num_active = static_cast<int>(in.value<std::int64_t>("bandit num_active"));
  saved.reselect = static_cast<BanditReselect>(in.value<std::int64_t>("bandit reselect"));
  saved.zeta = in.value<double>("bandit zeta");
  if (!(saved == params_)) in.fail("the saved bandit has other num_active, reselect or zeta than this one");
  auto active = in.values<std::uint8_t>("bandit active flags");
  auto success = in.values<double>("bandit successes");
  auto selection = in.values<double>("bandit selections");
  auto runs = in.values<std::int64_t>("bandit runs");
  if (active.size() != pool() || success.size() != pool() || selection.size() != pool() || runs.size() != pool())
    in.fail(fmt::format("the saved bandit is not of a pool of {}", pool()));
  active_ = std::move(active);
  success_ = std::move(success);
  selection_ = std::move(selection);
  runs_seen_ = std::move(runs);
}

}  // namespace qdmeta
