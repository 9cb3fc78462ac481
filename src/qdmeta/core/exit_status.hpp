#pragma once
// The command line's exit statuses (README, "Exit status"), for run_cli, the Distribution that
// refuses to start and the MPI workers that leave a broken job (so mpirun reports the same 3).
namespace qdmeta {

constexpr int kExitBadInput = 2;          // a config or input error, named in one line
constexpr int kExitRankFailed = 3;        // an MPI rank died mid-run; a checkpoint was written
constexpr int kExitEvaluationFailed = 4;  // a task's own code threw; the last checkpoint stands
constexpr int kExitInterrupted = 130;

}  // namespace qdmeta
