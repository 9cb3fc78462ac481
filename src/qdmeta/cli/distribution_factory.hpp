#pragma once
// The one place the command line chooses between MPI and a single process.
#include <memory>

#include "qdmeta/cli/distribution.hpp"

namespace qdmeta {

// Over MPI ranks when this CLI library was built with the MPI component (and MPI is then
// initialised when launched by mpirun), else the single-process Distribution.
std::unique_ptr<Distribution> make_distribution(int& argc, char**& argv);

}  // namespace qdmeta
