#pragma once
// What every algorithm offers to the run driver: one step at a time, counters, statistics
// and its elites as a flat table that io/ can write; and the ask/tell protocol that a step is
// made of, for callers that evaluate genotypes themselves.
//
// Ask/tell. A step is one or more requests. ask() returns the next request: a list of
// EvaluationJob (task, genotypes, output view), never empty, whose genotypes and outputs live in
// the algorithm's own buffers and stay valid until the matching tell(). The caller fills every
// job's outputs (fitness, base features, valid flag per row: evaluator.evaluate_jobs(jobs), or
// its own code) and calls tell(), or calls tell(results) with its own blocks, one per job, which
// are shape-checked and copied in. After tell(), step_in_progress() says whether the step needs
// more requests. step(evaluator) is exactly that loop, so a step driven by hand gives the same
// bits as step(). Out-of-order calls throw Error; checkpoints (save()) only between steps.
//
// A step that throws (the evaluator, a task, a meta-objective) is undone: step() puts back the
// state from before it, so the algorithm can step again and gives the bits it would have given
// had the failed step never run. Each algorithm saves before a step only what its steps change
// before their end (save_undo), by default its whole checkpoint state.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/evaluator.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct EvaluationCounters {
  std::int64_t bottom = 0;  // MAP-Elites offspring and initial population
  std::int64_t meta = 0;    // solution x task evaluations spent scoring maps (QD-Meta)
  std::int64_t total() const { return bottom + meta; }
  bool operator==(const EvaluationCounters&) const = default;
};

// Bytes of a generation's `rows` genotypes and their evaluations (fitness, base features,
// validity), the offspring buffers every algorithm allocates, for its memory estimate.
double offspring_bytes(double rows, const Task& task);

// Evaluation counters in checkpoints (shared by every algorithm).
void save_counters(BinaryWriter& out, const EvaluationCounters& c);
EvaluationCounters load_counters(BinaryReader& in);

// One meta-generation of QD-Meta, for meta.csv.
struct MetaGenerationRecord {
  std::int64_t meta_generation = 0;
  double meta_fitness_best = 0.0;
  double meta_fitness_mean = 0.0;
  double meta_fitness_sd = 0.0;  // population SD over the meta-population
  int generations = 0;           // MAP-Elites generations per map in this meta-generation
  std::int64_t states = 1;       // the controller's state count
  PopulationStats population;    // every map's archive after its G generations
};

class Algorithm {
 public:
  virtual ~Algorithm() = default;
  virtual std::string name() const = 0;
  // One step: a generation (QD-Meta: a meta-generation; the first step also evaluates the
  // initial population), as ask(), the evaluator's
  // evaluation of the jobs, tell(), until the step is complete. Parallel work inside ask() and
  // tell() (QD-Meta's rebuilds, CVT's cell lookups) runs on the evaluator's workers. When it
  // throws, the step is undone first (see above); an algorithm that cannot undo it (one that is
  // not checkpointable) is left mid-step.
  void step(Evaluator& evaluator);

  // The next request (see the protocol above). Throws Error when a request is already pending.
  std::span<const EvaluationJob> ask();
  // The pending request's results, written by the caller into the jobs' outputs. Throws Error
  // when no request is pending.
  void tell();
  // The same with the caller's own results, one block per job in job order; throws InputError
  // naming the job when a block's rows or base-feature columns do not match it, or when a valid
  // row has a non-finite fitness or a base feature outside [0, 1]. Everything is checked before
  // anything is copied, so a refused call leaves the request pending.
  void tell(std::span<const EvaluationBatch> results);
  bool request_pending() const { return pending_; }
  // True between a step's first ask() and its last tell().
  bool step_in_progress() const { return in_step_; }

  virtual std::int64_t generation() const = 0;
  // Every evaluation told so far: the rows of each request's bottom-level jobs, counted here once
  // tell() has taken them, and the meta-objective's own count (count_meta_evaluations).
  EvaluationCounters counters() const { return counters_; }
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

 protected:
  // Appends the next request's jobs to `jobs` (empty on entry); at least one.
  virtual void next_request(std::vector<EvaluationJob>& jobs) = 0;
  // Takes the results now in the last request's outputs; true when that completes the step.
  virtual bool take_results() = 0;
  // Called by step() before a step's first ask(), with its evaluator (CVT makes its centroids).
  virtual void before_step(Evaluator& /*evaluator*/) {}
  // True when ask() or tell() runs oneTBB work that step() should confine to the evaluator's
  // workers (each confinement costs a task arena entry, so cheap algorithms skip it).
  virtual bool parallel_inside() const { return false; }
  // Throws Error unless the algorithm is between steps; `what` names the refused operation.
  void require_between_steps(std::string_view what) const;
  // Adds the evaluations a meta-objective reports it spent (QD-Meta's scoring).
  void count_meta_evaluations(std::int64_t evaluations) { counters_.meta += evaluations; }
  // Puts back counters read from a checkpoint (load()).
  void restore_counters(const EvaluationCounters& counters) { counters_ = counters; }

  // Undoing a failed step. save_undo() runs before each step() and writes what the step may
  // change before it ends; load_undo() reads it back after the step threw, once the request is
  // dropped, and also resets the algorithm's own in-step state. The defaults are save() and
  // load() (a non-checkpointable algorithm cannot undo); an algorithm overrides them with less.
  virtual void save_undo(BinaryWriter& out) const;
  virtual void load_undo(BinaryReader& in);
  // For algorithms whose state changes only in the last tell() of a step: the undo is just the
  // generation count, and load_generation_undo throws Error when the generation has moved on
  // (the step failed after that tell() had taken the results).
  void save_generation_undo(BinaryWriter& out) const { out.value(generation()); }
  void load_generation_undo(BinaryReader& in) const;

 private:
  // After a step threw: the request dropped and the state from `undo` back; when that fails
  // too, the algorithm is left mid-step.
  void undo_step(std::string_view undo) noexcept;

  std::vector<EvaluationJob> jobs_;
  EvaluationCounters counters_;
  bool pending_ = false;
  bool in_step_ = false;
};

}  // namespace qdmeta
