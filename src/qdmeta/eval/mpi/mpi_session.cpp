#include "qdmeta/eval/mpi/mpi_session.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "qdmeta/core/notice.hpp"
#include "qdmeta/eval/mpi/mpi_protocol.hpp"

namespace qdmeta {

namespace {

using Clock = std::chrono::steady_clock;

// Sends what is queued for up to `limit`: a send to a dead rank may never complete.
void flush(mpi::Outbox& outbox, std::chrono::milliseconds limit) {
  const auto until = Clock::now() + limit;
  while (!outbox.empty() && Clock::now() < until) outbox.progress();
}

}  // namespace

bool launched_by_mpi() {
  // OpenMPI's mpirun, PMIx launchers (srun --mpi=pmix), PMI-1/2 launchers (srun, MPICH hydra).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

PeerIdentity PeerIdentity::self() {
  PeerIdentity me;
  me.pid = static_cast<std::int64_t>(getpid());
  std::string boot;
  std::ifstream("/proc/sys/kernel/random/boot_id") >> boot;
  char ns[64] = {};
  const ssize_t n = readlink("/proc/self/ns/pid", ns, sizeof ns - 1);
  const std::string machine = boot + "/" + std::string(ns, n > 0 ? static_cast<std::size_t>(n) : 0);
  if (!boot.empty() && n > 0 && machine.size() < me.machine.size())
    machine.copy(me.machine.data(), machine.size());
  return me;
}

bool PeerIdentity::same_machine_as(const PeerIdentity& other) const {
  return machine[0] != '\0' && machine == other.machine;
}

std::chrono::milliseconds heartbeat_timeout() {
  double seconds = 10;
  if (const char* text = std::getenv("QDMETA_MPI_TIMEOUT")) {
    char* end = nullptr;
    const double s = std::strtod(text, &end);
    if (end != text && s >= 1) seconds = s;  // below 1 s a busy machine could look dead
  }
  return std::chrono::milliseconds(static_cast<std::int64_t>(seconds * 1000));
}

MpiSession::MpiSession(int& argc, char**& argv) {
  if (!launched_by_mpi()) return;
  int provided = 0;
  // Rank 0 calls MPI from one thread at a time; workers from their main thread only.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &provided);
  active_ = true;
  // Errors come back as codes: the default handler would abort every rank without a checkpoint.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  self_ = PeerIdentity::self();
  peers_.assign(static_cast<std::size_t>(size_), PeerIdentity{});
  farewells_.assign(static_cast<std::size_t>(size_), false);
  dead_.assign(static_cast<std::size_t>(size_), false);
}

void MpiSession::meet(int rank, const PeerIdentity& peer) { peers_[static_cast<std::size_t>(rank)] = peer; }

bool MpiSession::gone(int rank) const {
  const PeerIdentity& p = peers_[static_cast<std::size_t>(rank)];
  if (p.pid <= 0 || !self_.same_machine_as(p)) return false;
  // A dead process that its launcher has not reaped yet still answers kill(); launchers reap
  // at once (that is how they learn of the death), so this is a matter of milliseconds.
  return kill(static_cast<pid_t>(p.pid), 0) != 0 && errno == ESRCH;
}

bool MpiSession::alive_here(int rank) const {
  const PeerIdentity& p = peers_[static_cast<std::size_t>(rank)];
  if (p.pid <= 0 || !self_.same_machine_as(p)) return false;
  return kill(static_cast<pid_t>(p.pid), 0) == 0 || errno != ESRCH;
}

bool MpiSession::any_farewell() const {
  for (int r = 1; r < size_; ++r)
    if (farewells_[static_cast<std::size_t>(r)]) return true;
  return false;
}

std::vector<int> MpiSession::silent_workers(std::chrono::milliseconds grace) {
  std::vector<int> silent;
  if (!active_ || rank_ != 0) return silent;
  bool found = false;  // by rank 0 itself: then no one else is about to say goodbye
  for (int r = 1; r < size_; ++r) {
    const auto i = static_cast<std::size_t>(r);
    found = found || dead_[i];
    if (dead_[i] && !farewells_[i]) silent.push_back(r);  // one that said goodbye was signalled
  }
  if (found) return silent;
  const auto until = Clock::now() + grace;
  for (;;) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, mpi::kBye, MPI_COMM_WORLD, &flag, &status);
    if (flag) {
      mpi::receive(status, MPI_COMM_WORLD);
      farewells_[static_cast<std::size_t>(status.MPI_SOURCE)] = true;
      continue;
    }
    silent.clear();
    for (int r = 1; r < size_; ++r)
      if (!farewells_[static_cast<std::size_t>(r)] && !alive_here(r)) silent.push_back(r);
    if (silent.empty() || Clock::now() >= until) return silent;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void MpiSession::release_survivors() {
  if (!active_ || rank_ != 0) return;
  mpi::Outbox outbox;
  for (int r = 1; r < size_; ++r) {
    const auto i = static_cast<std::size_t>(r);
    if (farewells_[i]) outbox.send({}, r, mpi::kStop, MPI_COMM_WORLD);
    else if (abandoned_ && !dead_[i]) outbox.send({}, r, mpi::kAbort, MPI_COMM_WORLD);
  }
  flush(outbox, std::chrono::milliseconds(100));
}

MpiSession::~MpiSession() {
  if (!active_ || abandoned_) return;
  if (rank_ == 0 && size_ > 1) {
    // MPI_Finalize waits for every rank, so first make sure that every rank is there: kStop,
    // each answers kStopped, then kFinalize. A rank that died (or stays silent for the
    // heartbeat timeout) means no MPI_Finalize: the others are told to exit (kAbort) instead.
    mpi::Outbox outbox;
    std::vector<bool> answered(static_cast<std::size_t>(size_), false);
    for (int r = 1; r < size_; ++r)
      if (!farewells_[static_cast<std::size_t>(r)] && !dead_[static_cast<std::size_t>(r)])
        outbox.send({}, r, mpi::kStop, MPI_COMM_WORLD);
    const auto until = Clock::now() + heartbeat_timeout();
    auto next_check = Clock::now();
    for (;;) {
      outbox.progress();
      int flag = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
      if (flag) {
        mpi::receive(status, MPI_COMM_WORLD);  // heartbeats and leftovers of an aborted request go too
        const auto from = static_cast<std::size_t>(status.MPI_SOURCE);
        if (status.MPI_TAG == mpi::kStopped) answered[from] = true;
        if (status.MPI_TAG == mpi::kBye) farewells_[from] = true;
        continue;
      }
      if (Clock::now() >= next_check) {
        next_check = Clock::now() + std::chrono::milliseconds(10);
        for (int r = 1; r < size_; ++r)
          if (!answered[static_cast<std::size_t>(r)] && gone(r)) mark_dead(r);
      }
      bool waiting = false;
      for (int r = 1; r < size_; ++r) {
        const auto i = static_cast<std::size_t>(r);
        waiting = waiting || (!answered[i] && !dead_[i] && !farewells_[i]);
      }
      if (!waiting) break;
      if (Clock::now() >= until) {
        for (int r = 1; r < size_; ++r)
          if (!answered[static_cast<std::size_t>(r)] && !farewells_[static_cast<std::size_t>(r)]) mark_dead(r);
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    std::string who;
    bool missing = false;
    for (int r = 1; r < size_; ++r) {
      missing = missing || dead_[static_cast<std::size_t>(r)] || farewells_[static_cast<std::size_t>(r)];
      if (dead_[static_cast<std::size_t>(r)]) who += fmt::format("{}{}", who.empty() ? "" : ", ", r);
    }
    if (missing) {
      if (!who.empty())
        notice(NoticeKind::kWarning, fmt::format("MPI rank{} {} stopped answering (crashed or killed) after rank 0's "
                                                 "last evaluation (what rank 0 wrote is unaffected)",
                                                 who.find(',') != std::string::npos ? "s" : "", who));
      for (int r = 1; r < size_; ++r) {
        const auto i = static_cast<std::size_t>(r);
        if (answered[i]) outbox.send({}, r, mpi::kAbort, MPI_COMM_WORLD);
        else if (farewells_[i]) outbox.send({}, r, mpi::kStop, MPI_COMM_WORLD);
      }
      flush(outbox, std::chrono::milliseconds(100));
      return;  // no MPI_Finalize: it would wait for the missing rank forever
    }
    for (int r = 1; r < size_; ++r) outbox.send({}, r, mpi::kFinalize, MPI_COMM_WORLD);
    while (!outbox.empty()) outbox.progress();
  }
  MPI_Finalize();
}

}  // namespace qdmeta
