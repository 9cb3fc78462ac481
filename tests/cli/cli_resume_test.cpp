// `qdmeta resume`: a killed or interrupted run continues to the same bits; a damaged or
// mismatched checkpoint is one clear line.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cli_suite.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliResume, AKilledRunResumesToTheSameBits) {
  const fs::path straight = fresh_dir("straight"), killed = fresh_dir("killed");
  const std::string config = checkpointing_config().string();
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + straight.string() + " --quiet").status, 0);
  // SIGKILL: no chance to clean up; the last periodic checkpoint (the third) must carry the run.
  signalled_at_checkpoint(std::string(QDMETA_BINARY) + " run --config " + config + " --out " + killed.string() +
                              " --quiet --threads 1",
                          3, "KILL");
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin")) << "killed before its first checkpoint";
  ASSERT_FALSE(fs::exists(killed / "summary.json")) << "finished before it was killed: raise the budget";
  const Outcome adapt = qdmeta_cli("adapt --run " + killed.string() + " --test dimension");
  EXPECT_EQ(adapt.status, 2) << adapt.output;  // not finished: nothing to test yet
  const Outcome r = qdmeta_cli("resume --out " + killed.string() + " --threads 2");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("resuming from checkpoint"), std::string::npos) << r.output;
  expect_same_run(straight, killed);
  const Outcome again = qdmeta_cli("resume --out " + killed.string());
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.output.find("already finished"), std::string::npos) << again.output;
}

TEST(CliResume, AnInterruptedRunSaysHowToResumeAndDoes) {
  const fs::path straight = fresh_dir("straight2"), stopped = fresh_dir("interrupted");
  const std::string config = checkpointing_config().string();
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + straight.string() + " --quiet").status, 0);
  const Outcome o =
      signalled_at_checkpoint(std::string(QDMETA_BINARY) + " run --config " + config + " --out " + stopped.string(), 2, "INT");
  ASSERT_EQ(o.status, 130) << o.output;  // interrupted
  EXPECT_NE(o.output.find("continue it with: qdmeta resume --out"), std::string::npos) << o.output;
  EXPECT_NE(slurp(stopped / "summary.json").find("\"interrupted\""), std::string::npos);
  ASSERT_EQ(qdmeta_cli("resume --out " + stopped.string() + " --quiet").status, 0);
  expect_same_run(straight, stopped);
}

TEST(CliResume, ADamagedOrMismatchedCheckpointIsAClearError) {
  const fs::path dir = fresh_dir("damaged");
  const std::string config = checkpointing_config().string();
  signalled_at_checkpoint(std::string(QDMETA_BINARY) + " run --config " + config + " --out " + dir.string() + " --quiet",
                          1, "INT");
  ASSERT_TRUE(fs::exists(dir / "checkpoint.bin"));
  const std::string good = slurp(dir / "checkpoint.bin");
  const auto expect_refused = [&](const std::string& why, const std::string& message) {
    const Outcome o = qdmeta_cli("resume --out " + dir.string() + " --quiet");
    EXPECT_EQ(o.status, 2) << why << "\n" << o.output;
    EXPECT_NE(o.output.find(message), std::string::npos) << why << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << o.output;
  };
  std::string flipped = good;
  flipped[flipped.size() / 2] = static_cast<char>(flipped[flipped.size() / 2] ^ 0x10);
  std::ofstream(dir / "checkpoint.bin", std::ios::binary) << flipped;
  expect_refused("one flipped byte", "damaged: checksum mismatch");
  std::ofstream(dir / "checkpoint.bin", std::ios::binary) << good.substr(0, good.size() - 100);
  expect_refused("truncated", "damaged");
  std::ofstream(dir / "checkpoint.bin", std::ios::binary) << "not a checkpoint at all";
  expect_refused("garbage", "is not a qdmeta checkpoint");
  std::ofstream(dir / "checkpoint.bin", std::ios::binary) << good;
  const std::string resolved = slurp(dir / "config.toml");
  std::ofstream(dir / "config.toml") << resolved << "\n[archive]\nbins = [50, 50]\n";
  const Outcome changed = qdmeta_cli("resume --out " + dir.string() + " --quiet");
  EXPECT_EQ(changed.status, 2) << changed.output;  // a duplicate table or a changed config: refused either way
  std::string edited = resolved;
  const auto at = edited.find("sigmoid_scale = 30");
  ASSERT_NE(at, std::string::npos) << resolved;
  edited.replace(at, 18, "sigmoid_scale = 31");
  std::ofstream(dir / "config.toml") << edited;
  expect_refused("config edited", "written for a different configuration");
  fs::remove(dir / "checkpoint.bin");
  std::ofstream(dir / "config.toml") << resolved;
  expect_refused("no checkpoint", "no checkpoint in");
}

}  // namespace
}  // namespace qdmeta
