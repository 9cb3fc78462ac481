#include "qdmeta/cli/distribution_factory.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <optional>

#include "qdmeta/cli/distribution.hpp"
#include "qdmeta/core/exit_status.hpp"

namespace qdmeta {
namespace {

// The rank count and this process's rank that an MPI launcher gave it (OpenMPI's mpirun, or a
// PMI launcher: MPICH's, srun --mpi=pmi2); {1, 0} when no launcher started it.
struct LauncherPlace {
  long ranks = 1, rank = 0;
};

LauncherPlace launcher_place() {
  const auto read = [](const char* size, const char* rank) -> std::optional<LauncherPlace> {
    const char* s = std::getenv(size);
    if (s == nullptr) return std::nullopt;
    const char* r = std::getenv(rank);
    return LauncherPlace{std::atol(s), r == nullptr ? 0 : std::atol(r)};
  };
  if (const auto p = read("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK")) return *p;
  if (const auto p = read("PMI_SIZE", "PMI_RANK")) return *p;
  return {};
}

// Every rank of a program without MPI that a launcher started several times: each would run the
// whole command into the same directory, so each exits at once, rank 0 saying why.
class NotAnMpiProgram final : public Distribution {
 public:
  std::optional<int> serve_if_worker() override { return kExitBadInput; }
};

}  // namespace

std::unique_ptr<Distribution> make_local_distribution(int& /*argc*/, char**& /*argv*/) {
  const LauncherPlace place = launcher_place();
  if (place.ranks <= 1) return std::make_unique<Distribution>();
  if (place.rank == 0)
    fmt::print(stderr,
               "qdmeta: error: started by an MPI launcher as {} ranks, but this program was built without MPI (it "
               "does not link qdmeta::mpi): each rank would run the whole command into the same directory. Link "
               "qdmeta::mpi (find_package(qdmeta COMPONENTS mpi)), or run it without the launcher (--threads N)\n",
               place.ranks);
  return std::make_unique<NotAnMpiProgram>();
}

}  // namespace qdmeta
