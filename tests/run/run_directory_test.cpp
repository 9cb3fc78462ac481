// A run directory's life (src/qdmeta/run/run_directory.hpp): started with the resolved config and
// its provenance; a directory that holds a run refused unless overwritten, and then only the old
// run's files removed; resume refused for no run, a finished run or a missing checkpoint; a
// finished run's stray checkpoint removed.
#include "qdmeta/run/run_directory.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "expect_input_error.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/plugin/config.hpp"
#include "run/run_dir_fixture.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

class RunDirectoryTest : public test::RunDirFixture {
 protected:
  void SetUp() override {
    RunDirFixture::SetUp();
    fs::remove_all(dir_);  // start_run_directory makes it
    config_ = toml::parse("algorithm = \"map-elites\"\nseed = 4\n[budget]\nevaluations = 3000\n"
                          "[task]\ndimensions = 4\n[archive]\nbins = [10, 10]\n");
  }
  toml::table config_;
};

TEST_F(RunDirectoryTest, StartWritesTheResolvedConfigWithItsProvenance) {
  const BuiltRun built = build_run(config_, "given.toml");
  start_run_directory(dir_, built, "given.toml", 3, false);
  const toml::table written = load_toml(dir_ / "config.toml");
  EXPECT_EQ(written["provenance"]["qdmeta_version"].value<std::string>(), std::string(kVersion));
  EXPECT_EQ(written["provenance"]["config_file"].value<std::string>(), "given.toml");
  EXPECT_EQ(written["provenance"]["threads"].value<std::int64_t>(), 3);
  EXPECT_EQ(written["provenance"][kConfigFingerprintKey].value<std::string>(),
            resolved_config_fingerprint(built.resolved));
  // Every key in force, defaults included: the file builds the same run again.
  EXPECT_EQ(written["map_elites"]["batch_size"].value<std::int64_t>(), built.resolved["map_elites"]["batch_size"].value<std::int64_t>());
  const BuiltRun again = build_run(written, (dir_ / "config.toml").string());
  EXPECT_EQ(again.settings.fingerprint, built.settings.fingerprint);
  EXPECT_EQ(again.resolved, built.resolved);
}

TEST_F(RunDirectoryTest, AnExperimentsRunCarriesItsConditionsFingerprint) {
  const BuiltRun built = build_run(config_, "given.toml");
  start_run_directory(dir_, built, "given.toml", 1, false, "0123456789abcdef");
  EXPECT_EQ(load_toml(dir_ / "config.toml")["provenance"][kConfigFingerprintKey].value<std::string>(),
            "0123456789abcdef");
}

TEST_F(RunDirectoryTest, AnyRunFileRefusesTheDirectoryUnlessOverwrite) {
  const BuiltRun built = build_run(config_, "given.toml");
  for (const std::string& file : run_files()) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write(file, "x");
    EXPECT_INPUT_ERROR(start_run_directory(dir_, built, "given.toml", 1, false),
                       dir_.string() + " already holds a run: pass --overwrite to replace it, or continue it with "
                                       "qdmeta resume --out " + dir_.string());
  }
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  fs::create_symlink(dir_ / "nowhere", dir_ / "metrics.csv");  // a dangling link counts
  EXPECT_THROW(start_run_directory(dir_, built, "given.toml", 1, false), InputError);
}

TEST_F(RunDirectoryTest, OverwriteRemovesTheOldRunsFilesAndNothingElse) {
  const BuiltRun built = build_run(config_, "given.toml");
  fs::create_directories(dir_);
  for (const std::string& file : run_files()) write(file, "old");
  for (const char* file : {"adapt-dimension.csv", "adapt-translation.csv", "generalisation.csv", "notes.txt",
                           "my-adapt-notes.csv"})
    write(file, "old");
  start_run_directory(dir_, built, "given.toml", 1, true);
  for (const std::string& file : run_files())
    EXPECT_EQ(fs::exists(dir_ / file), file == "config.toml") << file;
  EXPECT_NE(load_toml(dir_ / "config.toml")["provenance"].as_table(), nullptr);  // the new one
  EXPECT_FALSE(fs::exists(dir_ / "adapt-dimension.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "adapt-translation.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "generalisation.csv"));
  EXPECT_TRUE(fs::exists(dir_ / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir_ / "my-adapt-notes.csv"));
}

TEST_F(RunDirectoryTest, ResumeIsRefusedForNoRunAFinishedRunOrNoCheckpoint) {
  fs::create_directories(dir_);
  EXPECT_INPUT_ERROR((void)open_for_resume(dir_), dir_.string() + " holds no run (no config.toml)");
  start_run_directory(dir_, build_run(config_, "given.toml"), "given.toml", 1, false);
  const std::string no_checkpoint = input_error_message([&] { (void)open_for_resume(dir_); });
  EXPECT_TRUE(no_checkpoint.starts_with("no checkpoint in ")) << no_checkpoint;
  EXPECT_NE(no_checkpoint.find(dir_.string()), std::string::npos) << no_checkpoint;
  write_summary_saying(StopReason::kInterrupted);
  EXPECT_THROW((void)open_for_resume(dir_), InputError);
  EXPECT_TRUE(fs::exists(dir_ / "summary.json"));  // a refused resume changes nothing
  write_summary_saying(StopReason::kBudget);
  write(kCheckpointFile, "a checkpoint");
  EXPECT_INPUT_ERROR((void)open_for_resume(dir_),
                     "the run in " + dir_.string() + " has already finished: nothing to resume");
  EXPECT_TRUE(fs::exists(dir_ / kCheckpointFile));
}

TEST_F(RunDirectoryTest, OnlyAFinishedRunsCheckpointIsStray) {
  fs::create_directories(dir_);
  write("config.toml", "seed = 1\n");
  write(kCheckpointFile, "a checkpoint");
  EXPECT_FALSE(remove_stray_checkpoint(RunState(dir_)));  // unfinished: the checkpoint carries it
  write_summary_saying(StopReason::kInterrupted);
  EXPECT_FALSE(remove_stray_checkpoint(RunState(dir_)));
  EXPECT_TRUE(fs::exists(dir_ / kCheckpointFile));
  write_summary_saying(StopReason::kBudget);
  EXPECT_TRUE(remove_stray_checkpoint(RunState(dir_)));
  EXPECT_FALSE(fs::exists(dir_ / kCheckpointFile));
  EXPECT_FALSE(remove_stray_checkpoint(RunState(dir_)));  // nothing left to remove
}

}  // namespace
}  // namespace qdmeta
