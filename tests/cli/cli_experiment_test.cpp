// `qdmeta experiment` and `qdmeta report`: a killed experiment continues to the same results,
// a planned run started on its own is the experiment's, a malformed claim is refused before any run.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "cli_suite.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliExperiment, AKilledExperimentContinuesToTheSameResultsAndReports) {
  const fs::path clean = fresh_dir("experiment_clean"), killed = fresh_dir("experiment_killed");
  const std::string config = small_experiment().string();
  const Outcome first = qdmeta_cli("experiment --config " + config + " --out " + clean.string() + " --no-report");
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_NE(first.output.find("4 runs finished now, 0 resumed, 0 already finished; 8 test phases"), std::string::npos)
      << first.output;
  // The first run's first checkpoint (QD-Meta, replicate 1, comes first).
  signalled_at_checkpoint(std::string(QDMETA_BINARY) + " experiment --config " + config + " --out " + killed.string() +
                              " --no-report --quiet",
                          1, "KILL");
  ASSERT_TRUE(fs::exists(killed / "qd-meta-sarsa/seed-1/checkpoint.bin")) << "killed before the first checkpoint";
  const Outcome again = qdmeta_cli("experiment --config " + config + " --out " + killed.string());
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("1 resumed"), std::string::npos) << again.output;
  for (const char* cond : {"qd-meta-sarsa", "map-elites"})
    for (const char* seed : {"seed-1", "seed-2"}) {
      const fs::path a = clean / cond / seed, b = killed / cond / seed;
      for (const char* f : {"metrics.csv", "archive.csv", "adapt-dimension.csv", "adapt-translation.csv"})
        EXPECT_EQ(slurp(a / f), slurp(b / f)) << cond << "/" << seed << "/" << f;
    }
  EXPECT_EQ(slurp(clean / "qd-meta-sarsa/seed-2/meta.csv"), slurp(killed / "qd-meta-sarsa/seed-2/meta.csv"));
  // Seeds differ between replicates.
  EXPECT_NE(slurp(clean / "map-elites/seed-1/archive.csv"), slurp(clean / "map-elites/seed-2/archive.csv"));
  // The report: every figure and the tables.
  const std::string report = slurp(killed / "report.md");
  for (const char* figure : {"qd-statistics.png", "meta-fitness.png", "adaptation-dimension.png",
                             "adaptation-translation.png", "archives.png"}) {
    EXPECT_NE(report.find(std::string("figures/") + figure), std::string::npos) << figure;
    EXPECT_GT(fs::file_size(killed / "figures" / figure), 10'000u) << figure;
  }
  EXPECT_NE(report.find("| QD-Meta (SARSA) | 2 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| MAP-Elites | 2 |"), std::string::npos) << report;
  // QD-Meta's meta-population view, the claims table, and the CSV summaries behind them.
  EXPECT_NE(report.find("The meta-population view"), std::string::npos) << report;
  EXPECT_NE(report.find("| MAP-Elites stays under a billion elites | MAP-Elites "), std::string::npos) << report;
  EXPECT_NE(report.find("| **reproduced** |"), std::string::npos) << report;
  EXPECT_EQ(count_lines(slurp(killed / "data/runs.csv")), 5);  // a header and 2 conditions x 2 replicates
  EXPECT_GT(count_lines(slurp(killed / "data/curves.csv")), 100);
  // Everything finished: a third call runs nothing and only reports.
  const Outcome third = qdmeta_cli("experiment --config " + config + " --out " + killed.string() + " --no-report");
  EXPECT_NE(third.output.find("0 runs finished now, 0 resumed, 4 already finished; 0 test phases"), std::string::npos)
      << third.output;
  const Outcome other_budget =
      qdmeta_cli("experiment --config " + config + " --out " + killed.string() + " --evals 5000 --no-report");
  EXPECT_EQ(other_budget.status, 2) << other_budget.output;
}

TEST(CliExperiment, APlannedRunStartedOnItsOwnIsTheExperimentsRun) {
  // A batch system runs plan.tsv's lines with `qdmeta run`; the experiment then skips them. The
  // same run made by the experiment itself has the same bits.
  const fs::path planned = fresh_dir("experiment_planned"), whole = fresh_dir("experiment_whole");
  const std::string config = small_experiment().string();
  const Outcome plan = qdmeta_cli("experiment --config " + config + " --out " + planned.string() + " --evals 20000 --plan");
  ASSERT_EQ(plan.status, 0) << plan.output;
  EXPECT_NE(plan.output.find("4 runs planned"), std::string::npos) << plan.output;
  std::istringstream lines(slurp(planned / "plan.tsv"));
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "index\tcondition\tseed\tconfig\tdir\tconfig_fingerprint");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(lines, line)) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, '\t');) f.push_back(x);
    ASSERT_EQ(f.size(), 6u) << line;
    rows.push_back(f);
  }
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1][0], "2");
  EXPECT_EQ(rows[1][1], "map-elites");  // replicate-major: seed 1 of every condition first
  EXPECT_EQ(rows[1][2], "1");
  EXPECT_EQ(rows[1][4], (planned / "map-elites/seed-1").string());
  for (std::size_t k : {0u, 1u}) {  // QD-Meta and MAP-Elites (whose `set` budget --evals replaces), seed 1
    const Outcome r = qdmeta_cli("run --config " + rows[k][3] + " --seed " + rows[k][2] + " --out " + rows[k][4] + " --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
  }
  const Outcome rest = qdmeta_cli("experiment --config " + config + " --out " + planned.string() + " --evals 20000 --no-report");
  ASSERT_EQ(rest.status, 0) << rest.output;
  EXPECT_NE(rest.output.find("2 runs finished now, 0 resumed, 2 already finished"), std::string::npos) << rest.output;
  ASSERT_EQ(qdmeta_cli("experiment --config " + config + " --out " + whole.string() + " --evals 20000 --no-report --quiet").status, 0);
  for (const char* cond : {"qd-meta-sarsa", "map-elites"})
    for (const char* f : {"metrics.csv", "archive.csv", "adapt-dimension.csv"})
      EXPECT_EQ(slurp(planned / cond / "seed-1" / f), slurp(whole / cond / "seed-1" / f)) << cond << "/" << f;
  EXPECT_EQ(slurp(planned / "qd-meta-sarsa/seed-1/meta.csv"), slurp(whole / "qd-meta-sarsa/seed-1/meta.csv"));
}

TEST(CliExperiment, AMalformedClaimIsRefusedBeforeAnyRun) {
  std::string text = slurp(small_experiment());
  const auto at = text.find("kind = \"below\"");
  ASSERT_NE(at, std::string::npos) << text;
  text.insert(at, "colour = \"red\"\n");  // a key no claim has
  const fs::path config = write_config("bad-claim-experiment", text);
  const fs::path out = fresh_dir("bad_claim");
  const Outcome o = qdmeta_cli("experiment --config " + config.string() + " --out " + out.string() + " --evals 20000");
  EXPECT_EQ(o.status, 2) << o.output;
  EXPECT_EQ(count_lines(o.output), 1) << o.output;
  EXPECT_NE(o.output.find("qdmeta: error: " + config.string() + ":"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find(": [[claim]] 1: unknown key 'colour' for kind 'below'"), std::string::npos) << o.output;
  EXPECT_FALSE(fs::exists(out / "map-elites")) << "a run started before the claim was checked";
}

TEST(CliExperiment, ReportNeedsAnExperiment) {
  const Outcome o = qdmeta_cli("report " + fresh_dir("no_experiment").string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("no experiment.toml"), std::string::npos) << o.output;
}

}  // namespace
}  // namespace qdmeta
