// An experiment's kept summaries (--summaries) and subsets (--seeds, --conditions): the report
// from the summaries alone is the report from the runs, and a later call skips what was kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include "cli_suite.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

// Every file a report writes, by its path under `dir`.
std::map<std::string, std::string> report_files(const fs::path& dir) {
  std::map<std::string, std::string> files{{"report.md", slurp(dir / "report.md")}};
  for (const char* sub : {"data", "figures"})
    for (const auto& entry : fs::directory_iterator(dir / sub))
      files[std::string(sub) + "/" + entry.path().filename().string()] = slurp(entry.path());
  return files;
}

TEST(CliKeptSummaries, AReportFromKeptSummariesEqualsTheReportFromTheRuns) {
  // Each replicate range kept in one folder of summaries, as two machines would; the report from
  // the summaries alone is the report from the run directories, byte for byte.
  const fs::path runs = fresh_dir("summaries_runs"), kept = fresh_dir("summaries_kept"),
                 from_kept = fresh_dir("summaries_report"), elsewhere = fresh_dir("summaries_elsewhere");
  const std::string config = small_experiment().string();
  const std::string common = "experiment --config " + config + " --evals 20000 --no-report --summaries " + kept.string();
  const Outcome first = qdmeta_cli(common + " --out " + runs.string() + " --seeds 1");
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_NE(first.output.find("2 runs finished now, 0 resumed, 0 already finished; 4 test phases\n"
                              "2 summaries written, 0 runs skipped for the summary already in"),
            std::string::npos)
      << first.output;
  EXPECT_FALSE(fs::exists(runs / "map-elites/seed-2")) << "--seeds 1 ran replicate 2";
  const Outcome second = qdmeta_cli(common + " --out " + runs.string() + " --seeds 2-2");
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("2 summaries written, 0 runs skipped"), std::string::npos) << second.output;
  for (const char* run : {"qd-meta-sarsa/seed-1.json", "qd-meta-sarsa/seed-2.json", "map-elites/seed-1.json",
                          "map-elites/seed-2.json"}) {
    ASSERT_TRUE(fs::exists(kept / run)) << run;
    EXPECT_LT(fs::file_size(kept / run), 40'000u) << run;  // kilobytes, not the archive
  }
  EXPECT_NE(slurp(kept / "experiment.toml").find("config = '" + std::string(QDMETA_SOURCE_DIR) +
                                                 "/configs/rastrigin/map-elites.toml'"),
            std::string::npos);  // as the experiment file names it
  ASSERT_EQ(qdmeta_cli("report " + runs.string() + " --quiet").status, 0);
  const Outcome report = qdmeta_cli("report " + kept.string() + " --out " + from_kept.string() + " --quiet");
  ASSERT_EQ(report.status, 0) << report.output;
  const auto expected = report_files(runs), got = report_files(from_kept);
  EXPECT_EQ(expected.size(), 8u);  // report.md, runs.csv, curves.csv, 5 figures
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [name, bytes] : expected) EXPECT_TRUE(got.at(name) == bytes) << name << " differs";
  EXPECT_NE(expected.at("report.md").find("| MAP-Elites | 2 |"), std::string::npos);
  // Another machine with the summaries only: every run is skipped, none is made.
  const Outcome again = qdmeta_cli(common + " --out " + elsewhere.string());
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("0 runs finished now, 0 resumed, 0 already finished; 0 test phases\n"
                              "0 summaries written, 4 runs skipped"),
            std::string::npos)
      << again.output;
  EXPECT_FALSE(fs::exists(elsewhere / "map-elites/seed-1"));
  // A batch system's plan leaves out the runs whose summaries are kept.
  const fs::path planned = fresh_dir("summaries_plan");
  const Outcome plan = qdmeta_cli("experiment --config " + config + " --evals 20000 --plan --summaries " +
                                  kept.string() + " --out " + planned.string() + " --seeds 1-2");
  ASSERT_EQ(plan.status, 0) << plan.output;
  EXPECT_NE(plan.output.find("0 runs planned in " + (planned / "plan.tsv").string() + " (4 more are done: their "
                             "summaries are in " + kept.string() + ")"),
            std::string::npos)
      << plan.output;
  EXPECT_EQ(slurp(planned / "plan.tsv"), "index\tcondition\tseed\tconfig\tdir\tconfig_fingerprint\n");
  // A lost summary of a finished run is written again, the same bytes.
  const std::string summary = slurp(kept / "map-elites/seed-2.json");
  fs::remove(kept / "map-elites/seed-2.json");
  const Outcome rewritten = qdmeta_cli(common + " --out " + runs.string());
  EXPECT_NE(rewritten.output.find("0 runs finished now, 0 resumed, 1 already finished; 0 test phases\n"
                                  "1 summaries written, 3 runs skipped"),
            std::string::npos)
      << rewritten.output;
  EXPECT_EQ(slurp(kept / "map-elites/seed-2.json"), summary);
  // Summaries of another budget, or replicates past the experiment's, are refused before any run.
  const Outcome other_budget = qdmeta_cli("experiment --config " + config + " --evals 5000 --no-report --summaries " +
                                          kept.string() + " --out " + fresh_dir("summaries_other").string());
  EXPECT_EQ(other_budget.status, 2) << other_budget.output;
  EXPECT_NE(other_budget.output.find("its summaries were made with evaluations = 20000, this experiment has "
                                     "evaluations = 5000"),
            std::string::npos)
      << other_budget.output;
  const Outcome past = qdmeta_cli(common + " --out " + runs.string() + " --seeds 2-3");
  EXPECT_EQ(past.status, 2) << past.output;
  EXPECT_NE(past.output.find("replicates 2-3 are not within the experiment's 1-2"), std::string::npos) << past.output;
}

TEST(CliKeptSummaries, ConditionsRunsOnlyTheNamedConditionsAndTheRestFollowLater) {
  // A study's short conditions now, its long ones in another call: the summaries of both calls
  // together are the experiment's, and the second call skips what the first kept.
  const fs::path runs = fresh_dir("conditions_runs"), kept = fresh_dir("conditions_kept");
  const std::string config = small_experiment().string();
  const std::string common = "experiment --config " + config + " --evals 20000 --no-report --summaries " + kept.string() +
                             " --out " + runs.string();
  const Outcome some = qdmeta_cli(common + " --conditions map-elites");
  ASSERT_EQ(some.status, 0) << some.output;
  EXPECT_NE(some.output.find("(now map-elites)"), std::string::npos) << some.output;
  EXPECT_NE(some.output.find("2 runs finished now, 0 resumed, 0 already finished; 4 test phases\n"
                             "2 summaries written, 0 runs skipped"),
            std::string::npos)
      << some.output;
  EXPECT_TRUE(fs::exists(kept / "map-elites/seed-1.json") && fs::exists(kept / "map-elites/seed-2.json"));
  EXPECT_FALSE(fs::exists(runs / "qd-meta-sarsa")) << "--conditions map-elites ran QD-Meta";
  const Outcome rest = qdmeta_cli(common + " --seeds 2 --conditions qd-meta-sarsa,map-elites");
  ASSERT_EQ(rest.status, 0) << rest.output;
  EXPECT_NE(rest.output.find("(now replicates 2 of qd-meta-sarsa, map-elites)"), std::string::npos) << rest.output;
  EXPECT_NE(rest.output.find("1 runs finished now, 0 resumed, 0 already finished; 2 test phases\n"
                             "1 summaries written, 1 runs skipped"),
            std::string::npos)
      << rest.output;
  EXPECT_FALSE(fs::exists(runs / "qd-meta-sarsa/seed-1"));
  // A batch system's plan of the same subset.
  const fs::path planned = fresh_dir("conditions_plan");
  const Outcome plan = qdmeta_cli("experiment --config " + config + " --evals 20000 --plan --conditions qd-meta-sarsa "
                                  "--summaries " + kept.string() + " --out " + planned.string());
  ASSERT_EQ(plan.status, 0) << plan.output;
  const std::string plan_text = slurp(planned / "plan.tsv");
  EXPECT_TRUE(plan_text.starts_with("index\tcondition\tseed\tconfig\tdir\tconfig_fingerprint\n1\tqd-meta-sarsa\t1\t" +
                                    (planned / "qd-meta-sarsa/condition.toml").string() + "\t" +
                                    (planned / "qd-meta-sarsa/seed-1").string() + "\t"))
      << plan_text;
  EXPECT_EQ(std::count(plan_text.begin(), plan_text.end(), '\n'), 2) << plan_text;
  // A name the experiment does not have: one line that lists its conditions, nothing written.
  const fs::path untouched = fresh_dir("conditions_unknown") / "out";
  const Outcome unknown = qdmeta_cli("experiment --config " + config + " --evals 20000 --out " + untouched.string() +
                                     " --conditions map-elites,mapelites");
  EXPECT_EQ(unknown.status, 2) << unknown.output;
  EXPECT_EQ(count_lines(unknown.output), 1) << unknown.output;
  EXPECT_NE(unknown.output.find("experiment 'small' has no condition 'mapelites': its conditions are qd-meta-sarsa, "
                                "map-elites"),
            std::string::npos)
      << unknown.output;
  EXPECT_FALSE(fs::exists(untouched));
  const Outcome empty = qdmeta_cli("experiment --config " + config + " --out " + untouched.string() + " --conditions a,");
  EXPECT_EQ(empty.status, 2) << empty.output;
  EXPECT_NE(empty.output.find("conditions 'a,' must be condition directory names separated by commas"),
            std::string::npos)
      << empty.output;
}

}  // namespace
}  // namespace qdmeta
