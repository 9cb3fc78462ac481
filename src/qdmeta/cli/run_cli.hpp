#pragma once
// The whole qdmeta command line as a library call, so that a program with its own tasks,
// meta-objectives or algorithms gets every subcommand (run, resume, experiment, adapt, report,
// and `mpirun ... run` when it links qdmeta::mpi) without editing qdmeta: its main registers its
// plugins, then hands over.
//
//   int main(int argc, char** argv) {
//     qdmeta::register_builtin_plugins();
//     my::register_arm_task();
//     return qdmeta::run_cli(argc, argv);
//   }
//
// Register before run_cli on every process: under mpirun each rank runs this same main, and the
// worker ranks build their tasks from rank 0's config through the registries. docs/library.md
// is the tutorial.
#include <filesystem>

#include "qdmeta/cli/distribution_factory.hpp"
#ifdef QDMETA_WITH_MPI
#include "qdmeta/cli/mpi_distribution.hpp"
#endif

namespace qdmeta {

// Parses the command line and runs the subcommand; returns the exit status (0, 2 for bad input,
// 3 when an MPI rank died, 130 when interrupted). `tools_dir` holds report.py (`qdmeta report`)
// when neither $QDMETA_TOOLS_DIR nor ../share/qdmeta/tools beside the executable has it.
// `make_distribution` says where runs are evaluated (cli/distribution_factory.hpp).
int run_cli_with_tools(int argc, char** argv, const std::filesystem::path& tools_dir,
                       DistributionFactory make_distribution = make_local_distribution);

// The program's choices, from the targets it links: QDMETA_PACKAGE_TOOLS_DIR comes with
// qdmeta::cli (the source tree's tools/ in a build tree, the installed share/qdmeta/tools from
// find_package(qdmeta)); QDMETA_WITH_MPI with qdmeta::mpi, and with it `mpirun ... run`. Inline,
// so that the choice is the program's, not the one the CLI library was compiled with.
inline int run_cli(int argc, char** argv) {
#ifdef QDMETA_WITH_MPI
  const DistributionFactory distribution = make_mpi_distribution;
#else
  const DistributionFactory distribution = make_local_distribution;
#endif
#ifdef QDMETA_PACKAGE_TOOLS_DIR
  return run_cli_with_tools(argc, argv, QDMETA_PACKAGE_TOOLS_DIR, distribution);
#else
  return run_cli_with_tools(argc, argv, {}, distribution);
#endif
}

}  // namespace qdmeta
