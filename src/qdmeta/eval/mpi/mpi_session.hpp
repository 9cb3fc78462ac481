#pragma once
// The MPI side of the command line (optional component, QDMETA_WITH_MPI): rank 0 runs the
// algorithm and hands batches to the other ranks, which only evaluate (mpi_worker.hpp). No MPI
// header here, so callers compile without one.
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <vector>

namespace qdmeta {

// True when this process was started by an MPI launcher (mpirun, srun): a plain `qdmeta run`
// never initialises MPI, so it needs no launcher and behaves exactly as without MPI.
bool launched_by_mpi();

// Who a rank's process is, exchanged at start-up so that a rank can tell by itself, without the
// launcher, that a peer on the same machine has died: its pid, and the machine's boot id with
// the pid namespace (so pids are compared only where they mean the same process).
struct PeerIdentity {
  std::int64_t pid = 0;
  std::array<char, 96> machine{};  // "" when unknown (not Linux): no pid checks then
  static PeerIdentity self();
  bool same_machine_as(const PeerIdentity& other) const;
};

// Seconds without a word from a worker that holds pieces before rank 0 declares it dead (the
// heartbeat check, for ranks on other machines or hung ones): QDMETA_MPI_TIMEOUT, default 10.
std::chrono::milliseconds heartbeat_timeout();

// MPI for the life of the process: initialised when launched_by_mpi(), finalised at the end.
// On rank 0 the destructor first releases the workers (they exit), and skips MPI_Finalize (which
// would wait for a dead rank forever) when a rank does not answer.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }  // 1 without a launcher
  // After a failure: the job is being torn down (a rank died), so skip the release and
  // MPI_Finalize, which could wait for the dead rank forever.
  void abandon() { abandoned_ = true; }
  // Rank 0: ranks that died (see mark_dead) or else those that did not announce that they were
  // stopped by a signal (a signalled worker says so before exiting, a killed one cannot), waiting
  // up to `grace` for the announcements. A worker seen running on this machine is not silent:
  // when only rank 0 was signalled, the workers are alive and were never told.
  std::vector<int> silent_workers(std::chrono::milliseconds grace);
  // Rank 0: whether any worker said goodbye, i.e. the launcher is stopping the whole job.
  bool any_farewell() const;
  // Rank 0, last: lets the workers that said goodbye exit (they wait for this, because mpirun
  // stops forwarding rank 0's output once every other rank has exited); after abandon(), tells
  // the other live workers to exit too, so that none waits for the launcher's signals.
  void release_survivors();
  // Ranks > 0 that said goodbye (see silent_workers); shared with the evaluator.
  std::vector<bool>& farewells() { return farewells_; }

  // Liveness. Identities arrive with the handshake (meet); dead() is what rank 0 found out.
  const PeerIdentity& identity() const { return self_; }
  void meet(int rank, const PeerIdentity& peer);
  // True when `rank` runs on this machine and its process no longer exists.
  bool gone(int rank) const;
  // True when `rank` runs on this machine and its process still exists.
  bool alive_here(int rank) const;
  void mark_dead(int rank) { dead_[static_cast<std::size_t>(rank)] = true; }
  bool dead(int rank) const { return dead_[static_cast<std::size_t>(rank)]; }

 private:
  bool active_ = false;
  bool abandoned_ = false;
  int rank_ = 0;
  int size_ = 1;
  PeerIdentity self_;
  std::vector<PeerIdentity> peers_;
  std::vector<bool> farewells_, dead_;
};

}  // namespace qdmeta
