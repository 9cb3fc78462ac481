#pragma once
// The evaluators: serial, and oneTBB threads (thread_evaluator.cpp); the MPI one is in mpi/. The
// interface they implement, Evaluator, is core/evaluator.hpp's.
#include <functional>
#include <memory>

#include "qdmeta/core/evaluator.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

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
