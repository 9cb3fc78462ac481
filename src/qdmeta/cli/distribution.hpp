#pragma once
// Where a run's evaluations go beyond this process: nowhere (this class, a single process with
// threads) or over MPI ranks (cli/mpi_distribution.hpp, built with the MPI component). The
// command line holds one and never asks which it is, so MPI stays out of its code.
#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

class Distribution {
 public:
  virtual ~Distribution() = default;
  // Processes taking part (1 without MPI).
  virtual int ranks() const { return 1; }
  // On a worker rank: serves rank 0 until released and returns the exit status. On rank 0, or
  // without MPI: nullopt at once, and the caller goes on to parse its command line.
  virtual std::optional<int> serve_if_worker() { return std::nullopt; }
  // The evaluator of a run; `threads` may be changed (0 means one per rank under MPI). Setting
  // `*stop` makes a pending evaluation throw EvaluationAborted.
  virtual std::unique_ptr<Evaluator> make_evaluator(const BuiltRun& built, int& threads, const std::atomic<bool>* stop) {
    (void)built;
    (void)stop;
    return qdmeta::make_evaluator(threads);
  }
  // After a stopped run: the ranks that died or went silent, as "MPI rank 2 stopped answering
  // (crashed or killed); ", or "" when none.
  virtual std::string silent_ranks() { return {}; }
  // After the last word of a run: lets the surviving workers exit.
  virtual void release_survivors() {}
};

}  // namespace qdmeta
