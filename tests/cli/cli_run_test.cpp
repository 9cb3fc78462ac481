// A run from the command line: the files and columns README.md promises, fitness that is the task's
// of the stored genotype, the same bits at any thread count, refusal to overwrite.
#include <gtest/gtest.h>

#include <string>

#include "cli_suite.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliRun, RunWritesTheContractedFiles) {
  const fs::path out = fresh_dir("files");
  const Outcome o = qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 20000 --seed 3");
  ASSERT_EQ(o.status, 0) << o.output;
  for (const char* f : {"config.toml", "metrics.csv", "archive.csv", "summary.json"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  const std::string metrics = slurp(out / "metrics.csv");
  EXPECT_TRUE(metrics.starts_with(
      "evals,evals_bottom,evals_meta,generation,num_elites,coverage,qd_score,norm_qd_score,obj_max,obj_mean\n"));
  const std::string config = slurp(out / "config.toml");
  EXPECT_NE(config.find("seed = 3"), std::string::npos);
  EXPECT_NE(config.find("evaluations = 20000"), std::string::npos);
  EXPECT_NE(config.find("qdmeta_version"), std::string::npos);
  const std::string archive = slurp(out / "archive.csv");
  EXPECT_TRUE(archive.starts_with("index,objective,measures_0,measures_1,solution_0,solution_1,"));
  EXPECT_NE(o.output.find("results: " + out.string()), std::string::npos);
}

TEST(CliRun, EveryArchiveRowsFitnessIsRastriginOfItsGenotype) {
  const fs::path out = fresh_dir("fitness");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 50000 --quiet").status, 0);
  const EliteTable t = read_elites_csv(out / "archive.csv");
  ASSERT_GT(t.size(), 5000);
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), static_cast<std::size_t>(t.solutions.cols())});
    ASSERT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f)) << "row " << i;
    const auto cell = static_cast<std::int64_t>(std::min(99.0f, std::floor(t.measures(i, 0) * 100 + 1e-6f)) * 100 +
                                                std::min(99.0f, std::floor(t.measures(i, 1) * 100 + 1e-6f)));
    ASSERT_EQ(t.index[static_cast<std::size_t>(i)], cell) << "row " << i;
  }
}

TEST(CliRun, SameSeedSameBitsWithOneOrTwoThreads) {
  const fs::path a = fresh_dir("threads1"), b = fresh_dir("threads2");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + a.string() + " --evals 40000 --threads 1 --quiet").status, 0);
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + b.string() + " --evals 40000 --threads 2 --quiet").status, 0);
  EXPECT_EQ(slurp(a / "metrics.csv"), slurp(b / "metrics.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
}

TEST(CliRun, TheResolvedConfigRunsAgainToTheSameResult) {
  const fs::path a = fresh_dir("again1"), b = fresh_dir("again2");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + a.string() + " --evals 10000 --seed 5 --quiet").status, 0);
  const Outcome o = qdmeta_cli("run --config " + (a / "config.toml").string() + " --out " + b.string() + " --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
}

TEST(CliRun, RefusesADirectoryThatHoldsARunUnlessOverwrite) {
  const fs::path out = fresh_dir("refuse");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet").status, 0);
  const Outcome again = qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet");
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.output.find("already holds a run"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("--overwrite"), std::string::npos);
  EXPECT_EQ(count_lines(again.output), 1);
  EXPECT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet --overwrite").status, 0);
}

}  // namespace
}  // namespace qdmeta
