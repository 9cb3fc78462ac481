#pragma once
// What every algorithm offers to the run driver: one step at a time, counters, statistics
// and its elites as a flat table that io/ can write.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/types.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

struct EvaluationCounters {
  std::int64_t bottom = 0;  // MAP-Elites offspring and initial population
  std::int64_t meta = 0;    // solution x task evaluations spent scoring maps (QD-Meta)
  std::int64_t total() const { return bottom + meta; }
  bool operator==(const EvaluationCounters&) const = default;
};

// One meta-generation of QD-Meta, for meta.csv.
struct MetaGenerationRecord {
  std::int64_t meta_generation = 0;
  double meta_fitness_best = 0.0;
  double meta_fitness_mean = 0.0;
  double meta_fitness_sd = 0.0;  // population SD over the meta-population
  int generations = 0;           // MAP-Elites generations per map in this meta-generation
  std::int64_t states = 1;       // the controller's state count
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
  // The latest meta-generation (QD-Meta only; null for single-archive algorithms).
  virtual const MetaGenerationRecord* last_meta_record() const { return nullptr; }

  // Checkpoints, between steps: everything that step() reads, so that an algorithm built from
  // the same config and loaded continues bit-identically. Random streams are derived from
  // (seed, purpose, generation), so no generator state needs saving.
  virtual bool checkpointable() const { return false; }
  virtual void save(BinaryWriter& out) const;
  virtual void load(BinaryReader& in);
  // Algorithm-specific figures for summary.json, as (key, value) (e.g. AURORA's trainings).
  virtual std::vector<std::pair<std::string, double>> summary_extras() const { return {}; }
};

}  // namespace qdmeta
