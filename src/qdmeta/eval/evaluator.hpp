#pragma once
// Evaluators run a batch of genotypes through a task, results in batch order. Tasks are
// deterministic functions of the genotype, so any evaluator gives the same bits.
#include <functional>
#include <memory>
#include <span>

#include "qdmeta/core/task.hpp"

namespace qdmeta {

// One batch of a multi-task request: `task` evaluates `genotypes` into `out`.
struct EvaluationJob {
  const Task* task = nullptr;
  GenotypeView genotypes;
  EvaluationView out;
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

class SerialEvaluator final : public Evaluator {
 public:
  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    task.evaluate(genotypes, out);
  }
  int workers() const override { return 1; }
  void within_workers(const std::function<void()>& fn) override;  // a one-thread task arena
};

// Threads from oneTBB. `threads` = 0 uses every core. Rows are split into chunks of at most
// `chunk_rows`; a task that may not be shared gets one copy per thread. Once a batch of a task
// took under `cheap_batch_seconds` on the threads, evaluate() runs that task's batches on the
// calling thread (handing them out would cost more than it saves) until one takes over twice
// that; results never depend on it.
std::unique_ptr<Evaluator> make_thread_evaluator(int threads, Index chunk_rows = 32,
                                                 double cheap_batch_seconds = 200e-6);

// Serial for 1 thread, TBB otherwise.
std::unique_ptr<Evaluator> make_evaluator(int threads);

}  // namespace qdmeta
