#pragma once
// What the command-line tests share: running a shell command with its output, a scratch folder
// per test process (ctest runs a file's tests as parallel processes), reading a whole file.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace qdmeta::cli_test {

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr together
};

inline Outcome shell(const std::string& command_line) {
  const std::string command = command_line + " 2>&1";
  Outcome o;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return o;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) o.output += buffer;
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

// TMPDIR/qdmeta_<tag>_<pid>, made on first use.
inline std::filesystem::path process_scratch(const std::string& tag) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("qdmeta_" + tag + "_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A QD-Meta run of a few seconds (a small database) that checkpoints every `every_seconds`.
inline std::string small_qd_meta_config(const std::string& evaluations, const std::string& every_seconds) {
  return "algorithm = \"qd-meta\"\n[budget]\nevaluations = " + evaluations + "\n[checkpoint]\nevery_seconds = " +
         every_seconds + "\n[qd_meta]\ndatabase_capacity = 100_000\n";
}

// Two finished runs gave the same results, byte for byte, and the second kept no checkpoint.
inline void expect_same_run(const std::filesystem::path& a, const std::filesystem::path& b) {
  for (const char* f : {"metrics.csv", "meta.csv", "archive.csv"}) EXPECT_EQ(slurp(a / f), slurp(b / f)) << f;
  EXPECT_FALSE(std::filesystem::exists(b / "checkpoint.bin"));  // removed once the budget is reached
}

}  // namespace qdmeta::cli_test
