#include "qdmeta/cli/distribution_factory.hpp"

#ifdef QDMETA_WITH_MPI
#include "qdmeta/cli/mpi_distribution.hpp"
#endif

namespace qdmeta {

std::unique_ptr<Distribution> make_distribution(int& argc, char**& argv) {
#ifdef QDMETA_WITH_MPI
  return make_mpi_distribution(argc, argv);
#else
  (void)argc;
  (void)argv;
  return std::make_unique<Distribution>();
#endif
}

}  // namespace qdmeta
