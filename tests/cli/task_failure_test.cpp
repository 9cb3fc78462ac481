// A user's task that fails: one that throws ends the run in one line naming the task, the
// generation and what was kept, with its own exit status (4, not a config error's 2); one that
// never marks a solution valid says so instead of reporting an empty archive as zeros.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_helpers.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;
using cli_test::Outcome;
using cli_test::shell;

const std::string kFaulty = QDMETA_FAULTY_BINARY;

fs::path config_of(const std::string& name, const std::string& task_table) {
  return cli_test::faulty_task_config("task_failure", name, task_table);
}

Outcome run(const std::string& name, const std::string& task_table) {
  const fs::path out = cli_test::process_scratch("task_failure") / name;
  fs::remove_all(out);
  return shell(kFaulty + " run --quiet --threads 1 --config " + config_of(name, task_table).string() + " --out " +
               out.string());
}

std::string out_dir(const std::string& name) { return (cli_test::process_scratch("task_failure") / name).string(); }

TEST(TaskFailure, ATaskThatThrowsEndsTheRunInOneLineNamingTheGenerationAndTheCheckpoint) {
  // Rows 0-499 are generation 1, then 100 a generation: row 1,000 is the first of generation 7.
  const Outcome o = run("throws-later", "[task]\nname = \"throws\"\nthrow_after = 1000");
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_EQ(o.output, "qdmeta: error: evaluation failed in generation 7 of the run: task 'throws' threw on row 0 "
                      "of the batch: simulator diverged; its last checkpoint is kept: fix the task, then continue with: qdmeta resume --out " +
                          out_dir("throws-later") + "\n");
  EXPECT_TRUE(fs::exists(fs::path(out_dir("throws-later")) / "checkpoint.bin"));
}

TEST(TaskFailure, ATaskThatThrowsBeforeTheFirstCheckpointSaysToRunAgain) {
  const Outcome o = run("throws-first", "[task]\nname = \"throws\"\nthrow_after = 0");
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_NE(o.output.find("evaluation failed in generation 1 of the run: task 'throws' threw on row 0 of the batch: "
                          "simulator diverged; no "
                          "checkpoint was written yet: fix the task, then run it again into " + out_dir("throws-first")),
            std::string::npos)
      << o.output;
}

TEST(TaskFailure, ARunWithNoValidSolutionSaysSoInWords) {
  const Outcome o = run("never-valid", "[task]\nname = \"never-valid\"");
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(o.output, "qdmeta: warning: no solution was valid in 5000 evaluations, so the archive is empty (its best "
                      "and mean are not defined): a task marks a solution valid by setting its row's valid flag\n");
}

TEST(TaskFailure, TheProgressAndSummaryOfARunWithNoValidSolutionShowNoZerosAsBestOrMean) {
  const fs::path out = cli_test::process_scratch("task_failure") / "never-valid-loud";
  fs::remove_all(out);
  const Outcome o = shell(kFaulty + " run --threads 1 --config " +
                          config_of("never-valid-loud", "[task]\nname = \"never-valid\"").string() + " --out " +
                          out.string());
  EXPECT_EQ(o.status, 0) << o.output;
  // Not a terminal: one progress line per tenth of the budget, each saying there is no elite.
  EXPECT_NE(o.output.find("100.0%  5000 / 5000 evals"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("no elite yet  ETA"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("evaluations in "), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("; the archive is empty (no elite, so no best or mean)\nresults: " + out.string()),
            std::string::npos)
      << o.output;
  for (const char* zeros : {"best 0", "mean 0", "elites 0", "0 elites"})
    EXPECT_EQ(o.output.find(zeros), std::string::npos) << zeros << " in " << o.output;
}

TEST(TaskFailure, AnExperimentNamesTheConditionAndSeedOfTheFailingRun) {
  const fs::path dir = cli_test::process_scratch("task_failure");
  const fs::path config = config_of("throws-in-experiment", "[task]\nname = \"throws\"\nthrow_after = 1000");
  std::ofstream(dir / "experiment.toml") << "name = \"faulty\"\nreplicates = 1\n[[condition]]\nname = \"throwing\"\n"
                                           "config = \"" << config.string() << "\"\n";
  fs::remove_all(dir / "experiment-out");
  const Outcome o = shell(kFaulty + " experiment --quiet --threads 1 --no-report --config " +
                          (dir / "experiment.toml").string() + " --out " + (dir / "experiment-out").string());
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_EQ(o.output, "qdmeta: error: evaluation failed in condition 'throwing' seed 1 (run): task 'throws' threw on "
                      "row 0 of the batch: simulator diverged; the "
                      "finished runs and this run's last checkpoint are kept: fix the task, then run the same command "
                      "again to continue\n");
}

}  // namespace
}  // namespace qdmeta
