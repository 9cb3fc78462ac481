#include "qdmeta/emitters/ranking.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/fused.hpp"

namespace qdmeta {

std::string to_string(EmitterRanker value) { return std::string(enum_to_string(kEmitterRankerNames, value)); }

EmitterRanker emitter_ranker_from_string(std::string_view text) {
  return enum_from_string(kEmitterRankerNames, "emitter ranker", text);
}

std::vector<RankKey> rank_keys(EmitterRanker ranker, const EmitterResults& results, std::span<const double> direction) {
  if (needs_direction(ranker) && static_cast<Index>(direction.size()) != results.measures.cols) {
    throw InputError(fmt::format("rank_keys: the {} ranker has a direction of {} values for {} measures",
                                 to_string(ranker), direction.size(), results.measures.cols));
  }
  const auto projection = [&](std::size_t r) {
    const Real* m = results.measures.row(static_cast<Index>(r));
    double sum = 0.0;
    for (std::size_t j = 0; j < direction.size(); ++j) sum = fused(static_cast<double>(m[j]), direction[j], sum);
    return sum;
  };
  std::vector<RankKey> keys(static_cast<std::size_t>(results.rows()));
  for (std::size_t r = 0; r < keys.size(); ++r) {
    const ThresholdOutcome& outcome = results.outcomes[r];
    const int status = static_cast<int>(outcome.status);  // kNew 2 > kImproved 1 > kNotAdded 0
    const double objective = results.objectives[r];
    switch (ranker) {
      case EmitterRanker::kImprovement: keys[r] = {0, outcome.improvement}; break;
      case EmitterRanker::kTwoStageImprovement: keys[r] = {status, outcome.improvement}; break;
      case EmitterRanker::kObjective: keys[r] = {0, objective}; break;
      case EmitterRanker::kTwoStageObjective: keys[r] = {status > 0 ? 1 : 0, objective}; break;
      case EmitterRanker::kRandomDirection: keys[r] = {0, projection(r)}; break;
      case EmitterRanker::kTwoStageRandomDirection: keys[r] = {status, projection(r)}; break;
    }
  }
  return keys;
}

std::vector<int> rank_order(const std::vector<RankKey>& keys) {
  std::vector<int> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&keys](int a, int b) {
    const RankKey& ka = keys[static_cast<std::size_t>(a)];
    const RankKey& kb = keys[static_cast<std::size_t>(b)];
    return ka.stage != kb.stage ? ka.stage > kb.stage : ka.value > kb.value;
  });
  return order;
}

}  // namespace qdmeta
