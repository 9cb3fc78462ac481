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

// Runs `command` (a qdmeta run or experiment) with the test hook that makes it send itself
// `signal` right after its `checkpoint`-th checkpoint (QDMETA_TEST_SIGNAL_AT_CHECKPOINT): the
// moment is the program's own, never a race between a timer and the run.
inline Outcome signalled_at_checkpoint(const std::string& command, int checkpoint, const std::string& signal) {
  return shell("QDMETA_TEST_SIGNAL_AT_CHECKPOINT=" + std::to_string(checkpoint) + ":" + signal + " " + command);
}

// Starts `command` with the hook set to stop it (SIGSTOP) at its `checkpoint`-th checkpoint,
// waits until it has stopped (at most a minute), runs `during` while it holds its directories,
// then sends `signal`, lets it continue and waits for it. Returns the command's outcome.
inline Outcome while_stopped_at_checkpoint(const std::string& command, int checkpoint, const std::string& during,
                                           const std::string& signal) {
  // `exec`, so that $! is the program itself, not a shell around it.
  return shell("QDMETA_TEST_SIGNAL_AT_CHECKPOINT=" + std::to_string(checkpoint) + ":STOP exec " + command +
               " & pid=$!; for i in $(seq 6000); do grep -q '^State:[[:space:]]*T' /proc/$pid/status && break; "
               "sleep 0.01; done; " + during + "; kill -" + signal + " $pid; kill -CONT $pid; wait $pid");
}

// TMPDIR/qdmeta_<tag>_<pid>, made on first use.
inline std::filesystem::path process_scratch(const std::string& tag) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("qdmeta_" + tag + "_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

// TMPDIR/qdmeta_<tag>_<pid>/<name>, removed if it was there.
inline std::filesystem::path fresh_scratch_dir(const std::string& tag, const std::string& name) {
  const std::filesystem::path dir = process_scratch(tag) / name;
  std::filesystem::remove_all(dir);
  return dir;
}

// TMPDIR/qdmeta_<tag>_<pid>/<name>.toml, holding `text`.
inline std::filesystem::path write_scratch_config(const std::string& tag, const std::string& name,
                                                  const std::string& text) {
  const std::filesystem::path path = process_scratch(tag) / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

// TMPDIR/qdmeta_<tag>_<pid>/<name>.toml: a MAP-Elites run of the faulty-task binary's task
// `task_table` (its [task] table): 500 random genotypes, then batches of 100, 5,000 evaluations.
inline std::filesystem::path faulty_task_config(const std::string& tag, const std::string& name,
                                                const std::string& task_table) {
  return write_scratch_config(tag, name,
                              "algorithm = \"map-elites\"\nseed = 1\n[budget]\nevaluations = 5000\n" + task_table +
                                  "\n[map_elites]\nbatch_size = 100\ninitial_population = 500\n[archive]\nbins = [8, 8]\n"
                                  "measures = [0, 1]\n");
}

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A QD-Meta run of a few seconds (a small database) that checkpoints every `every_seconds` (0:
// after every step).
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
