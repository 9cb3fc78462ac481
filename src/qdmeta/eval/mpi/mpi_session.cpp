#include "qdmeta/eval/mpi/mpi_session.hpp"

#include <cstdlib>
#include <thread>

#include "qdmeta/eval/mpi/mpi_protocol.hpp"

namespace qdmeta {

bool launched_by_mpi() {
  // OpenMPI's mpirun, PMIx launchers (srun --mpi=pmix), PMI-1/2 launchers (srun, MPICH hydra).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
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
  farewells_.assign(static_cast<std::size_t>(size_), false);
}

std::vector<int> MpiSession::silent_workers(std::chrono::milliseconds grace) {
  std::vector<int> silent;
  if (!active_ || rank_ != 0) return silent;
  const auto until = std::chrono::steady_clock::now() + grace;
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
      if (!farewells_[static_cast<std::size_t>(r)]) silent.push_back(r);
    if (silent.empty() || std::chrono::steady_clock::now() >= until) return silent;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void MpiSession::release_survivors() {
  if (!active_ || rank_ != 0) return;
  mpi::Outbox outbox;
  for (int r = 1; r < size_; ++r)
    if (farewells_[static_cast<std::size_t>(r)]) outbox.send({}, r, mpi::kStop, MPI_COMM_WORLD);
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(100);
  while (!outbox.empty() && std::chrono::steady_clock::now() < until) outbox.progress();
}

MpiSession::~MpiSession() {
  if (!active_ || abandoned_) return;
  if (rank_ == 0) {
    mpi::Outbox outbox;
    for (int r = 1; r < size_; ++r)
      if (!farewells_[static_cast<std::size_t>(r)]) outbox.send({}, r, mpi::kStop, MPI_COMM_WORLD);
    while (!outbox.empty()) outbox.progress();
  }
  MPI_Finalize();
}

}  // namespace qdmeta
