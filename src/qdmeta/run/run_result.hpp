#pragma once
// How a run ended: what run_to_budget returns and summary.json records.
#include <cstdint>
#include <string>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

enum class StopReason { kBudget, kInterrupted };
inline constexpr EnumNames<StopReason, 2> kStopReasonNames{{{StopReason::kBudget, "budget"},
                                                            {StopReason::kInterrupted, "interrupted"}}};

struct RunResult {
  StopReason reason = StopReason::kBudget;
  std::string message;
  EvaluationCounters counters;
  std::int64_t evals = 0;  // what the budget counts
  std::int64_t generations = 0;
  ArchiveStats stats;
  double wall_seconds = 0.0;
};

}  // namespace qdmeta
