#pragma once
// The tables a run logs as it goes: metrics.csv (one row per logging period, plus the last
// generation) and meta.csv (QD-Meta: one row per meta-generation). Their columns are declared
// once, in run_tables.cpp; the final metrics point also goes into summary.json.
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/io/table.hpp"

namespace qdmeta {

// Where a run stands at a generation boundary.
struct RunPoint {
  std::int64_t evals = 0;  // what the budget counts
  EvaluationCounters counters;
  std::int64_t generation = 0;
  ArchiveStats stats;
};
RunPoint run_point(const Algorithm& algorithm, std::int64_t evals);

// One finished meta-generation, with the run's counters after it.
struct MetaPoint {
  const MetaGenerationRecord& record;
  EvaluationCounters counters;
  std::int64_t evals = 0;
};

const Table<RunPoint>& metrics_table();
const Table<MetaPoint>& meta_table();

// Their headers, as resume checks them against the files.
inline const std::vector<std::string>& metrics_columns() { return metrics_table().header(); }
inline const std::vector<std::string>& meta_columns() { return meta_table().header(); }

}  // namespace qdmeta
