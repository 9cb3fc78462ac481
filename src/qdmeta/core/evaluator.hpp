#pragma once
// The evaluator contract: a batch of genotypes through a task, results in batch order. Tasks are
// deterministic functions of the genotype, so any evaluator gives the same bits. Algorithms and
// meta-objectives see evaluators only through this interface; the implementations (serial,
// oneTBB threads, MPI ranks) are in eval/.
#include <functional>
#include <span>

#include "qdmeta/core/evaluation_batch.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

// One batch of a multi-task request: `task` evaluates `genotypes` into `out`.
struct EvaluationJob {
  const Task* task = nullptr;
  GenotypeView genotypes;
  EvaluationView out;
  // Counted as bottom-level evaluations when told (Algorithm::tell); false for a meta-objective's
  // batches, whose evaluations the objective itself reports.
  bool bottom_level = true;
};

class Evaluator {
 public:
  virtual ~Evaluator() = default;
  virtual void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) = 0;
  // Several batches, possibly of different tasks (a meta-fitness's environments), as one
  // request, so that a distributed evaluator can balance them together.
  virtual void evaluate_jobs(std::span<const EvaluationJob> jobs) {
    for (const EvaluationJob& j : jobs) evaluate(*j.task, j.genotypes, j.out);
  }
  virtual int workers() const = 0;
  // Runs body(0) ... body(n - 1), possibly in parallel on this evaluator's workers. Callers
  // make the result independent of the order (each index owns its outputs and RNG stream).
  virtual void parallel_for(Index n, const std::function<void(Index)>& body) {
    for (Index i = 0; i < n; ++i) body(i);
  }
  // Runs `fn` so that any oneTBB parallelism inside it uses this evaluator's workers only.
  virtual void within_workers(const std::function<void()>& fn) { fn(); }
  // True when evaluate() may throw EvaluationAborted midway (distributed workers that can die):
  // the run driver then keeps the state before each step to checkpoint it on failure.
  virtual bool may_abort() const { return false; }
};

}  // namespace qdmeta
