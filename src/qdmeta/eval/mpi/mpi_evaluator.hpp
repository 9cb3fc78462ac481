#pragma once
// Rank 0's evaluator under MPI: batches are cut into pieces of shrinking size (guided
// self-scheduling) handed out dynamically (up to two in flight per worker, so a worker never
// waits for its next piece; episodes differ in cost),
// rank 0 evaluates pieces too between polls, and every result is written at its batch position.
// Tasks are deterministic functions of a row, so the bits do not depend on the ranks or on who
// evaluated what. A task travels as its index in the evaluation-task list (BuiltRun), which each
// worker rebuilds from rank 0's resolved config; the lists are compared at start-up.
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

class MpiSession;

// "name (genes -> base features)" per task: what rank 0 and the workers compare.
std::string describe_tasks(const std::vector<Task>& tasks);

// Sends the config to every worker and waits until each has built the same tasks (Error naming
// the rank otherwise). `threads`: threads per rank (rank 0's own pieces, parallel_for, and each
// worker's pieces). Setting `*stop` (SIGTERM from mpirun when a rank dies) makes a pending
// evaluate() throw EvaluationAborted at once. A task not in `tasks` is evaluated on rank 0 alone.
std::unique_ptr<Evaluator> make_mpi_evaluator(MpiSession& session, std::vector<Task> tasks,
                                              const std::string& config_text, int threads,
                                              const std::atomic<bool>* stop);

}  // namespace qdmeta
