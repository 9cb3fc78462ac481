#pragma once
// How the command line gets its Distribution (cli/distribution.hpp), chosen by the program that
// calls run_cli: this single-process one, or make_mpi_distribution (cli/mpi_distribution.hpp)
// when the program links qdmeta::mpi, whose QDMETA_WITH_MPI compile definition reaches
// run_cli.hpp. So qdmeta::cli itself never needs MPI, and a program that does not ask for the mpi
// component links it where MPI is absent. No heavy header here: run_cli.hpp includes this one.
#include <memory>

namespace qdmeta {

class Distribution;

// Makes the Distribution once, first thing in run_cli; may take MPI's arguments out of argv.
using DistributionFactory = std::unique_ptr<Distribution> (*)(int& argc, char**& argv);

// A single process (its threads): every program's, and the only one without qdmeta::mpi.
std::unique_ptr<Distribution> make_local_distribution(int& argc, char**& argv);

}  // namespace qdmeta
