#pragma once
// What the files of cli_test share (cli_run_test.cpp, cli_input_test.cpp, ...): the program under
// test, this process's scratch folder, the configs the tests start from. Each file takes them all
// with `using namespace cli_suite;`.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_helpers.hpp"

namespace qdmeta::cli_suite {

namespace fs = std::filesystem;
using cli_test::expect_same_run;
using cli_test::Outcome;
using cli_test::signalled_at_checkpoint;
using cli_test::slurp;

inline Outcome qdmeta_cli(const std::string& args) { return cli_test::shell(std::string(QDMETA_BINARY) + " " + args); }

// This process's own scratch folder: ctest runs tests as parallel processes (and a Release
// and a sanitizer suite may run at once), so no two of them may share a path.
inline fs::path scratch() { return cli_test::process_scratch("cli_test"); }

inline fs::path fresh_dir(const std::string& name) {
  const fs::path dir = scratch() / name;
  fs::remove_all(dir);
  return dir;
}

inline fs::path write_config(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

inline int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

inline std::string config_path() { return std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml"; }

// A small QD-Meta run (SARSA control) that checkpoints after every step and takes a few seconds.
inline fs::path checkpointing_config() { return write_config("resume", cli_test::small_qd_meta_config("500_000", "0")); }

// Two conditions (a QD-Meta run of a few seconds that checkpoints often, plain MAP-Elites) x 2
// replicates, both tests.
inline fs::path small_experiment() {
  const std::string me = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml";
  return write_config("experiment", "name = \"small\"\nreplicates = 2\ntests = [\"dimension\", \"translation\"]\n"
                                    "[[condition]]\nname = \"QD-Meta (SARSA)\"\nconfig = \"" + checkpointing_config().string() +
                                    "\"\n[[condition]]\nname = \"MAP-Elites\"\nconfig = \"" + me + "\"\n"
                                    "set = { budget = { evaluations = 100_000 } }\n"
                                    "[[claim]]\ntext = \"MAP-Elites stays under a billion elites\"\nkind = \"below\"\n"
                                    "measure = \"population:num_elites\"\nconditions = [\"MAP-Elites\"]\nvalue = 1e9\n");
}

}  // namespace qdmeta::cli_suite
