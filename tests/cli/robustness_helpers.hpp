#pragma once
// What the robustness tests share (robustness_test.cpp, robustness_rerun_test.cpp): the program
// under test, quoting for sh, a scratch folder, runs stopped at a checkpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_helpers.hpp"

namespace qdmeta::robustness {

namespace fs = std::filesystem;
using cli_test::Outcome;
using cli_test::shell;
using cli_test::signalled_at_checkpoint;

inline fs::path scratch() { return cli_test::process_scratch("robustness_test"); }

inline fs::path fresh_dir(const std::string& name) {
  const fs::path dir = scratch() / name;
  fs::remove_all(dir);
  return dir;
}

inline fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// One word for sh, whatever it holds: single quotes, each ' written as '\''.
inline std::string quote(const std::string& word) {
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// QDMETA_TEST_BINARY runs the same tests against another build (e.g. an older one, to see them fail).
inline const std::string kBinary = quote(std::getenv("QDMETA_TEST_BINARY") ? std::getenv("QDMETA_TEST_BINARY") : QDMETA_BINARY);

inline Outcome qdmeta_cli(const std::string& args) { return shell(kBinary + " " + args); }

inline int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

inline std::string map_elites_config() { return quote(std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml"); }

// A QD-Meta run of a few seconds with only the first checkpoint (after the first step): the
// periodic one never comes.
inline fs::path first_checkpoint_only_config() {
  return write_file("first-checkpoint.toml", cli_test::small_qd_meta_config("600_000", "1e9"));
}

// A QD-Meta run interrupted at its first checkpoint: config.toml, metrics.csv, meta.csv,
// checkpoint.bin and summary.json ("interrupted") are all there.
inline fs::path interrupted_run(const std::string& name) {
  const fs::path dir = fresh_dir(name);
  const Outcome o = signalled_at_checkpoint(kBinary + " run --config " + quote(first_checkpoint_only_config().string()) +
                                                " --out " + quote(dir.string()) + " --quiet --threads 1",
                                            1, "INT");
  EXPECT_EQ(o.status, 130) << o.output;
  return dir;
}

}  // namespace qdmeta::robustness
