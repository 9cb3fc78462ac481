#pragma once
// The MPI implementation of the command line's Distribution (cli/distribution.hpp), in the
// qdmeta::mpi library. No MPI header here, nor a heavy one: run_cli.hpp includes this one in
// programs that link qdmeta::mpi.
#include <memory>

#include "qdmeta/cli/distribution_factory.hpp"

namespace qdmeta {

// Initialises MPI when launched by mpirun (MpiSession) and holds it for the object's life.
// Worker ranks build their tasks from rank 0's resolved config with build_run(), through the
// registries: every rank must have registered the same plugins before this call.
std::unique_ptr<Distribution> make_mpi_distribution(int& argc, char**& argv);

}  // namespace qdmeta
