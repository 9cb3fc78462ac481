#pragma once
// What every algorithm offers to the run driver: one step at a time, counters, statistics
// and its elites as a flat table that io/ can write.
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/core/types.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

struct EvaluationCounters {
  std::int64_t bottom = 0;  // MAP-Elites offspring and initial population
  std::int64_t meta = 0;    // solution x task evaluations spent scoring maps (QD-Meta)
  std::int64_t total() const { return bottom + meta; }
  bool operator==(const EvaluationCounters&) const = default;
};

// Elites in pyribs's column convention: cell index, objective, measures, solution (+ base).
struct EliteTable {
  std::vector<std::int64_t> index;
  std::vector<Real> objective;
  RowMatrix measures;
  RowMatrix solutions;
  RowMatrix base_features;  // zero columns when the algorithm keeps none
  Index size() const { return static_cast<Index>(index.size()); }
};

class Algorithm {
 public:
  virtual ~Algorithm() = default;
  virtual std::string name() const = 0;
  // One generation (the first call evaluates the initial population).
  virtual void step(Evaluator& evaluator) = 0;
  virtual std::int64_t generation() const = 0;
  virtual EvaluationCounters counters() const = 0;
  virtual ArchiveStats stats() const = 0;
  virtual EliteTable elites() const = 0;
};

}  // namespace qdmeta
