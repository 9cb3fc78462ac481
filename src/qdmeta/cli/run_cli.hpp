#pragma once
// The whole qdmeta command line as a library call, so that a program with its own tasks,
// meta-objectives or algorithms gets every subcommand (run, resume, experiment, adapt, report,
// and `mpirun ... run`) without editing qdmeta: its main registers its plugins, then hands over.
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

namespace qdmeta {

// Parses the command line and runs the subcommand; returns the exit status (0, 2 for bad input,
// 3 when an MPI rank died, 130 when interrupted). `tools_dir` holds report.py (`qdmeta report`)
// when neither $QDMETA_TOOLS_DIR nor ../share/qdmeta/tools beside the executable has it.
int run_cli_with_tools(int argc, char** argv, const std::filesystem::path& tools_dir);

// QDMETA_PACKAGE_TOOLS_DIR comes with the qdmeta::cli target: the source tree's tools/ in a
// build tree, the installed share/qdmeta/tools from find_package(qdmeta).
inline int run_cli(int argc, char** argv) {
#ifdef QDMETA_PACKAGE_TOOLS_DIR
  return run_cli_with_tools(argc, argv, QDMETA_PACKAGE_TOOLS_DIR);
#else
  return run_cli_with_tools(argc, argv, {});
#endif
}

}  // namespace qdmeta
