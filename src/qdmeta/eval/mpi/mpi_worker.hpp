#pragma once
// The loop of ranks > 0: wait for a config, build its evaluation tasks, evaluate the pieces rank
// 0 sends, one at a time on a compute thread while the main thread keeps talking to rank 0.
// Workers write no files and print nothing: errors go to rank 0, which reports them.
#include <functional>
#include <string>
#include <vector>

#include "qdmeta/core/task.hpp"

namespace qdmeta {

class MpiSession;

// The evaluation tasks of a resolved config (the CLI: build_run(..., BuildScope::kTasksOnly)).
using TaskListBuilder = std::function<std::vector<Task>(const std::string& config_text)>;

// Serves rank 0 until it sends stop (returns 0 once rank 0 has seen every rank answer) or a
// SIGTERM/SIGINT arrives (tells rank 0, calls session.abandon() and returns 128 + the signal).
// Exits at once with status 3, without MPI_Finalize, when rank 0 says that a rank died or when
// rank 0's process vanishes (same machine). Sends a heartbeat while it holds pieces.
// Test hook: QDMETA_TEST_KILL_RANK=k and QDMETA_TEST_KILL_AFTER=m make rank k kill itself
// (SIGKILL) when its (m+1)-th piece arrives, as a crashed worker would vanish (m = stop: when
// rank 0's closing kStop arrives, after the run);
// QDMETA_TEST_KILL_SIGNAL=STOP makes it stop (SIGSTOP) instead, as a hung one would.
int run_mpi_worker(MpiSession& session, const TaskListBuilder& build);

}  // namespace qdmeta
