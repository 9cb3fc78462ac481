#pragma once
// The MPI side of the command line (optional component, QDMETA_WITH_MPI): rank 0 runs the
// algorithm and hands batches to the other ranks, which only evaluate (mpi_worker.hpp). No MPI
// header here, so callers compile without one.
#include <chrono>
#include <memory>
#include <vector>

namespace qdmeta {

// True when this process was started by an MPI launcher (mpirun, srun): a plain `qdmeta run`
// never initialises MPI, so it needs no launcher and behaves exactly as without MPI.
bool launched_by_mpi();

// MPI for the life of the process: initialised when launched_by_mpi(), finalised at the end.
// On rank 0 the destructor first releases the workers (they exit).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }  // 1 without a launcher
  // Rank 0 after a failure: the job is being torn down (a rank died), so skip the release and
  // MPI_Finalize, which could wait for the dead rank forever.
  void abandon() { abandoned_ = true; }
  // Rank 0: ranks that announced they were stopped by a signal (a signalled worker says so
  // before exiting, a killed one cannot). Waits up to `grace` for them.
  std::vector<int> silent_workers(std::chrono::milliseconds grace);
  // Rank 0, last: lets the workers that said goodbye exit. They wait for this, because mpirun
  // stops forwarding rank 0's output once every other rank has exited.
  void release_survivors();
  // Ranks > 0 that said goodbye (see silent_workers); shared with the evaluator.
  std::vector<bool>& farewells() { return farewells_; }

 private:
  bool active_ = false;
  bool abandoned_ = false;
  int rank_ = 0;
  int size_ = 1;
  std::vector<bool> farewells_;
};

}  // namespace qdmeta
