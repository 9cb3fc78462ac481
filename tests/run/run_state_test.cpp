// RunState: what a run directory holds, read once. An empty or missing directory holds no run;
// config.toml makes a run and gives its budget; summary.json says whether it finished (only a
// `budget` stop is finished) and is kept as read; checkpoint.bin is seen; a damaged file is an
// InputError naming it.
#include "qdmeta/run/run_state.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "qdmeta/core/error.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "run/run_dir_fixture.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using RunStateTest = test::RunDirFixture;

TEST_F(RunStateTest, AMissingOrEmptyDirectoryHoldsNoRun) {
  for (const fs::path& dir : {dir_, dir_ / "missing"}) {
    const RunState state(dir);
    EXPECT_FALSE(state.has_run());
    EXPECT_FALSE(state.stop_reason().has_value());
    EXPECT_FALSE(state.finished());
    EXPECT_FALSE(state.has_checkpoint());
    EXPECT_THROW((void)state.config(), InputError);
  }
}

TEST_F(RunStateTest, ConfigMakesARunAndGivesItsBudget) {
  write("config.toml", "[budget]\nevaluations = 1234\n");
  const RunState state(dir_);
  EXPECT_TRUE(state.has_run());
  EXPECT_FALSE(state.finished());  // no summary yet: still going, or killed
  EXPECT_EQ(state.budget(), 1234);
  write("config.toml", "seed = 3\n");
  EXPECT_EQ(RunState(dir_).budget(), -1);
  EXPECT_EQ(state.budget(), 1234);  // parsed once and kept
}

TEST_F(RunStateTest, OnlyABudgetStopIsFinished) {
  write("config.toml", "seed = 1\n");
  write_summary_saying(StopReason::kInterrupted);
  EXPECT_EQ(RunState(dir_).stop_reason(), StopReason::kInterrupted);
  EXPECT_FALSE(RunState(dir_).finished());
  write_summary_saying(StopReason::kBudget);
  EXPECT_EQ(RunState(dir_).stop_reason(), StopReason::kBudget);
  EXPECT_TRUE(RunState(dir_).finished());
}

TEST_F(RunStateTest, TheSummaryIsReadOnceAndKept) {
  write("config.toml", "seed = 1\n");
  write_summary_saying(StopReason::kBudget);
  const RunState state(dir_);
  fs::remove(dir_ / "summary.json");  // what the state read stays what it says
  ASSERT_TRUE(state.summary().has_value());
  EXPECT_TRUE(state.finished());
  EXPECT_EQ(std::get<std::string>(*state.summary()->find("algorithm")), "map-elites");
  EXPECT_FALSE(RunState(dir_).summary().has_value());
}

TEST_F(RunStateTest, SeesACheckpoint) {
  write(kCheckpointFile, "x");
  EXPECT_TRUE(RunState(dir_).has_checkpoint());
}

TEST_F(RunStateTest, ADamagedFileIsAnInputErrorNamingIt) {
  write("config.toml", "[budget\n");
  const RunState state(dir_);
  try {
    (void)state.config();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("config.toml"), std::string::npos) << e.what();
  }
  write("summary.json", "{\"stop_reason\": ");
  try {
    (void)RunState(dir_);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("summary.json"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace qdmeta
