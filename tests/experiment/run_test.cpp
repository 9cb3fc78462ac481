// The run driver: budget semantics, metrics rows, interruption, files written.
#include "qdmeta/experiment/run.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "qdmeta/experiment/config.hpp"
#include "qdmeta/io/csv.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_run_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

BuiltRun small_run(std::int64_t evals, std::int64_t log_every) {
  toml::table config = load_toml(fs::path(QDMETA_SOURCE_DIR) / "configs/rastrigin/map-elites.toml");
  config.insert_or_assign("log", toml::table{{"every", log_every}});
  return build_run(config, "map-elites.toml", {std::nullopt, evals});
}

std::vector<std::string> lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(Run, StopsAtTheFirstGenerationAtOrPastTheBudget) {
  const fs::path dir = fresh_dir("budget");
  BuiltRun built = small_run(10'001, 1000);
  SerialEvaluator evaluator;
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir);
  EXPECT_EQ(r.reason, StopReason::kBudget);
  EXPECT_EQ(r.evals, 10'400);  // 2,000 + 21 x 400: the overshoot is real and reported
  EXPECT_EQ(r.generations, 22);
  const auto rows = lines(dir / "metrics.csv");
  EXPECT_EQ(rows.front(), "evals,evals_bottom,evals_meta,generation,num_elites,coverage,qd_score,norm_qd_score,obj_max,obj_mean");
  EXPECT_TRUE(rows.back().starts_with("10400,10400,0,22,"));
  EXPECT_TRUE(fs::exists(dir / "archive.csv"));
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "archive.csv.tmp"));
  EXPECT_EQ(read_elites_csv(dir / "archive.csv").size(), r.stats.num_elites);
}

TEST(Run, LogsARowPerPeriodAndTheLastGeneration) {
  const fs::path dir = fresh_dir("period");
  BuiltRun built = small_run(20'000, 4000);
  SerialEvaluator evaluator;
  run_to_budget(*built.algorithm, evaluator, built.settings, dir);
  const auto rows = lines(dir / "metrics.csv");
  // Rows at the first generation at or past 0, 4000, 8000, 12000, 16000, 20000.
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_TRUE(rows[1].starts_with("2000,"));
  EXPECT_TRUE(rows[2].starts_with("4000,"));
  EXPECT_TRUE(rows[6].starts_with("20000,"));
}

TEST(Run, InterruptionStopsAtAGenerationBoundaryAndStillWritesTheArchive) {
  const fs::path dir = fresh_dir("interrupt");
  BuiltRun built = small_run(1'000'000, 10000);
  SerialEvaluator evaluator;
  std::atomic<bool> stop{false};
  const RunResult r = run_to_budget(
      *built.algorithm, evaluator, built.settings, dir, [&](const RunProgress& p) { stop = p.generation >= 5; }, &stop);
  EXPECT_EQ(r.reason, StopReason::kInterrupted);
  EXPECT_EQ(r.generations, 5);
  EXPECT_EQ(read_elites_csv(dir / "archive.csv").size(), r.stats.num_elites);
  EXPECT_TRUE(lines(dir / "metrics.csv").back().starts_with("3600,"));
}

}  // namespace
}  // namespace qdmeta
