// The command line end to end: the files and columns README.md promises, exit status 2 with a
// one-line message on bad input, refusal to overwrite, and the same bits at any thread count.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cli_helpers.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using cli_test::Outcome;
using cli_test::shell;
using cli_test::slurp;

Outcome qdmeta_cli(const std::string& args) { return shell(std::string(QDMETA_BINARY) + " " + args); }

// This process's own scratch folder: ctest runs tests as parallel processes (and a Release
// and a sanitizer suite may run at once), so no two of them may share a path.
fs::path scratch() { return cli_test::process_scratch("cli_test"); }

using cli_test::signalled_at_checkpoint;

std::string config_path() { return std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml"; }

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = scratch() / name;
  fs::remove_all(dir);
  return dir;
}

fs::path write_config(const std::string& name, const std::string& text) {
  const fs::path path = scratch() / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

int count_lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(Cli, RunWritesTheContractedFiles) {
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

TEST(Cli, EveryArchiveRowsFitnessIsRastriginOfItsGenotype) {
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

TEST(Cli, SameSeedSameBitsWithOneOrTwoThreads) {
  const fs::path a = fresh_dir("threads1"), b = fresh_dir("threads2");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + a.string() + " --evals 40000 --threads 1 --quiet").status, 0);
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + b.string() + " --evals 40000 --threads 2 --quiet").status, 0);
  EXPECT_EQ(slurp(a / "metrics.csv"), slurp(b / "metrics.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
}

TEST(Cli, TheResolvedConfigRunsAgainToTheSameResult) {
  const fs::path a = fresh_dir("again1"), b = fresh_dir("again2");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + a.string() + " --evals 10000 --seed 5 --quiet").status, 0);
  const Outcome o = qdmeta_cli("run --config " + (a / "config.toml").string() + " --out " + b.string() + " --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
}

TEST(Cli, RefusesADirectoryThatHoldsARunUnlessOverwrite) {
  const fs::path out = fresh_dir("refuse");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet").status, 0);
  const Outcome again = qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet");
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.output.find("already holds a run"), std::string::npos) << again.output;
  EXPECT_NE(again.output.find("--overwrite"), std::string::npos);
  EXPECT_EQ(count_lines(again.output), 1);
  EXPECT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + out.string() + " --evals 3000 --quiet --overwrite").status, 0);
}

TEST(Cli, TheTopLevelHelpListsWhatAConfigMayName) {
  const Outcome o = qdmeta_cli("--help");
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.output.find("algorithm: map-elites, qd-meta, cvt-map-elites, aurora, cma-me, cma-mae\n"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("  [mutation] kind: gaussian, discrete-step, uniform-resample, iso-line\n  [control] kind: "
                          "static, sarsa\n  [archive] kind: grid\n  [feature_map] kind: select\n"),
            std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("[task] name = \"rastrigin\": [meta_fitness] kind translation, dimension; adapt --test "
                          "dimension, translation"),
            std::string::npos)
      << o.output;
  // RHex is either a registered task or listed as missing from the build, never silent.
  EXPECT_TRUE(o.output.find("[task] name = \"rhex\"") != std::string::npos ||
              o.output.find("not in this build: rhex") != std::string::npos)
      << o.output;
}

TEST(Cli, BadInputIsOneLineAndExitStatusTwo) {
  const fs::path out = fresh_dir("bad");
  const fs::path unknown_key = write_config("unknown_key", "algorithm = \"map-elites\"\n[task]\ndimensionz = 3\n");
  const fs::path wrong_type = write_config("wrong_type", "[task]\ndimensions = \"twenty\"\n");
  const fs::path out_of_range = write_config("range", "[mutation]\nrate = 1.5\n");
  const fs::path bad_choice = write_config("choice", "algorithm = \"map-elite\"\n");
  const fs::path zero_budget = write_config("zero", "[budget]\nevaluations = 0\n");
  const fs::path syntax = write_config("syntax", "[task\n");
  const struct {
    std::string args;
    std::string expected;
  } cases[] = {
      {"--config " + unknown_key.string(), "task.dimensionz"},
      {"--config " + wrong_type.string(), "task.dimensions must be an integer"},
      {"--config " + out_of_range.string(), "mutation.rate = 1.5"},
      {"--config " + bad_choice.string(), "\"map-elites\""},
      {"--config " + zero_budget.string(), "budget.evaluations = 0"},
      {"--config " + syntax.string(), syntax.string() + ":1:"},
      {"--config /nonexistent/qdmeta.toml", "/nonexistent/qdmeta.toml does not exist"},
      {"--config " + config_path() + " --evals 0", "--evals"},
  };
  for (const auto& c : cases) {
    const Outcome o = qdmeta_cli("run " + c.args + " --out " + out.string());
    EXPECT_EQ(o.status, 2) << c.args << "\n" << o.output;
    EXPECT_NE(o.output.find(c.expected), std::string::npos) << c.args << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << c.args << "\n" << o.output;
    EXPECT_FALSE(fs::exists(out / "metrics.csv")) << c.args;
  }
}

TEST(Cli, QdMetaRunWritesMetaCsvAndTheBestMapWithBaseFeatures) {
  const fs::path a = fresh_dir("qdmeta1"), b = fresh_dir("qdmeta2");
  const std::string config = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/qdmeta-translation-static.toml";
  const Outcome o = qdmeta_cli("run --config " + config + " --out " + a.string() + " --evals 60000 --threads 1 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + b.string() + " --evals 60000 --threads 2 --quiet").status, 0);
  const std::string meta = slurp(a / "meta.csv");
  EXPECT_TRUE(meta.starts_with("meta_generation,evals,evals_bottom,evals_meta,meta_fitness_best,meta_fitness_mean,"
                               "meta_fitness_sd,generations,states,population_num_elites_mean,population_num_elites_se,"
                               "population_obj_mean_mean,population_obj_mean_se,population_obj_max_mean,"
                               "population_obj_max_se,population_qd_score_mean,population_qd_score_se\n"));
  // 2,000 initial + 3 meta-generations x 10 maps x 5 generations x 400 = 62,000 >= 60,000.
  EXPECT_EQ(count_lines(meta), 4);
  EXPECT_NE(meta.find("\n3,62000,62000,"), std::string::npos) << meta;
  EXPECT_EQ(meta, slurp(b / "meta.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
  const EliteTable t = read_elites_csv(a / "archive.csv");
  ASSERT_GT(t.size(), 100);
  ASSERT_EQ(t.base_features.cols(), 20);
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), 20});
    ASSERT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f)) << "row " << i;
  }
}

TEST(Cli, SarsaControlChoosesAndLogsGenerationsPerMetaGeneration) {
  const fs::path out = fresh_dir("sarsa");
  const std::string config = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/qdmeta-translation.toml";
  const Outcome o = qdmeta_cli("run --config " + config + " --out " + out.string() + " --evals 400000 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  std::istringstream meta(slurp(out / "meta.csv"));
  std::string line;
  std::getline(meta, line);
  std::int64_t previous = 2000;  // the initial population
  std::set<int> chosen;
  int rows = 0;
  while (std::getline(meta, line)) {
    std::vector<std::string> f;
    std::stringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 17u) << line;
    const int g = std::stoi(f[7]);
    EXPECT_GE(g, 1);
    EXPECT_LE(g, 10);
    // The logged G is the one that ran: 10 maps x G generations x 400 offspring.
    EXPECT_EQ(std::stoll(f[2]) - previous, 10 * g * 400) << line;
    EXPECT_EQ(std::stoll(f[8]), 1) << "too few meta-generations for the state tree to split";
    previous = std::stoll(f[2]);
    chosen.insert(g);
    ++rows;
  }
  EXPECT_GE(rows, 5);
  EXPECT_GE(chosen.size(), 3u);  // the controller changes G over time
}

TEST(Cli, AdaptWritesTheTestPhaseCurveOfAFinishedRun) {
  const fs::path run = fresh_dir("adapt");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + run.string() + " --evals 20000 --quiet").status, 0);
  for (const std::string test : {"dimension", "translation"}) {
    const Outcome one = qdmeta_cli("adapt --run " + run.string() + " --test " + test + " --threads 1");
    ASSERT_EQ(one.status, 0) << one.output;
    EXPECT_NE(one.output.find("120 functions x 100 evaluations"), std::string::npos) << one.output;
    const std::string curve = slurp(run / ("adapt-" + test + ".csv"));
    ASSERT_EQ(qdmeta_cli("adapt --run " + run.string() + " --test " + test + " --threads 2 --quiet").status, 0);
    EXPECT_EQ(curve, slurp(run / ("adapt-" + test + ".csv")));  // any thread count, same bits
    std::istringstream rows(curve);
    std::string line;
    std::getline(rows, line);
    EXPECT_EQ(line, "evaluations,best_mean,best_se");
    double previous = -1e300;
    int count = 0;
    while (std::getline(rows, line)) {
      ++count;
      EXPECT_EQ(std::stoi(line), count);
      const double best = std::stod(line.substr(line.find(',') + 1));
      EXPECT_GE(best, previous);
      EXPECT_GE(best, -2000.0);  // scores are max(-M, f)
      EXPECT_LE(best, 0.0);
      previous = best;
    }
    EXPECT_EQ(count, 100);
  }
  const Outcome bad = qdmeta_cli("adapt --run " + run.string() + " --test sideways");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("valid tests are dimension, translation"), std::string::npos) << bad.output;
  fs::remove(run / "summary.json");  // as if the run had not finished
  const Outcome unfinished = qdmeta_cli("adapt --run " + run.string() + " --test dimension --budget 5");
  EXPECT_EQ(unfinished.status, 2);
  EXPECT_NE(unfinished.output.find("has not finished"), std::string::npos) << unfinished.output;
}

// A small QD-Meta run (SARSA control) that checkpoints after every step and takes a few seconds.
fs::path checkpointing_config() {
  return write_config("resume", cli_test::small_qd_meta_config("500_000", "0"));
}

using cli_test::expect_same_run;

TEST(Cli, AKilledRunResumesToTheSameBits) {
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

TEST(Cli, AnInterruptedRunSaysHowToResumeAndDoes) {
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

TEST(Cli, ADamagedOrMismatchedCheckpointIsAClearError) {
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

// Two conditions (a QD-Meta run of a few seconds that checkpoints often, plain MAP-Elites) x 2
// replicates, both tests.
fs::path small_experiment() {
  const std::string me = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml";
  return write_config("experiment", "name = \"small\"\nreplicates = 2\ntests = [\"dimension\", \"translation\"]\n"
                                    "[[condition]]\nname = \"QD-Meta (SARSA)\"\nconfig = \"" + checkpointing_config().string() +
                                    "\"\n[[condition]]\nname = \"MAP-Elites\"\nconfig = \"" + me + "\"\n"
                                    "set = { budget = { evaluations = 100_000 } }\n"
                                    "[[claim]]\ntext = \"MAP-Elites stays under a billion elites\"\nkind = \"below\"\n"
                                    "measure = \"population:num_elites\"\nconditions = [\"MAP-Elites\"]\nvalue = 1e9\n");
}

TEST(Cli, AKilledExperimentContinuesToTheSameResultsAndReports) {
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

TEST(Cli, APlannedRunStartedOnItsOwnIsTheExperimentsRun) {
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

// Every file a report writes, by its path under `dir`.
std::map<std::string, std::string> report_files(const fs::path& dir) {
  std::map<std::string, std::string> files{{"report.md", slurp(dir / "report.md")}};
  for (const char* sub : {"data", "figures"})
    for (const auto& entry : fs::directory_iterator(dir / sub))
      files[std::string(sub) + "/" + entry.path().filename().string()] = slurp(entry.path());
  return files;
}

TEST(Cli, AReportFromKeptSummariesEqualsTheReportFromTheRuns) {
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

TEST(Cli, ConditionsRunsOnlyTheNamedConditionsAndTheRestFollowLater) {
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

TEST(Cli, AMalformedClaimIsRefusedBeforeAnyRun) {
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

TEST(Cli, ReportNeedsAnExperiment) {
  const Outcome o = qdmeta_cli("report " + fresh_dir("no_experiment").string());
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("no experiment.toml"), std::string::npos) << o.output;
}

TEST(Cli, AuroraRunStoresRastriginOfEachGenotypeWithLatentMeasuresAndBaseFeatures) {
  const fs::path out = fresh_dir("aurora");
  const std::string config = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/aurora.toml";
  const Outcome o = qdmeta_cli("run --config " + config + " --out " + out.string() + " --evals 12000 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  const std::string archive = slurp(out / "archive.csv");
  EXPECT_TRUE(archive.starts_with("index,objective,measures_0,measures_1,solution_0,"));
  EXPECT_NE(archive.find(",base_0,"), std::string::npos);
  const EliteTable t = read_elites_csv(out / "archive.csv");
  ASSERT_GT(t.size(), 500);
  ASSERT_EQ(t.measures.cols(), 2);
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), static_cast<std::size_t>(t.solutions.cols())});
    ASSERT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f)) << "row " << i;
    ASSERT_EQ(t.index[static_cast<std::size_t>(i)], i);  // container slots
    ASSERT_TRUE(t.base_features.row(i) == t.solutions.row(i)) << "row " << i;  // Rastrigin: base = genotype
  }
  const std::string summary = slurp(out / "summary.json");
  EXPECT_NE(summary.find("\"algorithm\": \"aurora\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"trainings\""), std::string::npos) << summary;
}

TEST(Cli, AuroraSameSeedSameBitsWithOneOrTwoThreads) {
  const std::string config = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/aurora.toml";
  const fs::path a = fresh_dir("aurora_threads1"), b = fresh_dir("aurora_threads2");
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + a.string() + " --evals 10000 --threads 1 --quiet").status, 0);
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + b.string() + " --evals 10000 --threads 2 --quiet").status, 0);
  EXPECT_EQ(slurp(a / "metrics.csv"), slurp(b / "metrics.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
}

// A small CVT-MAP-Elites run (200 centroids, its own cache directory): every archive row's
// fitness is Rastrigin of its genotype and its cell the nearest centroid of its measures; the
// same bits with 1 and 2 threads, and again when the centroids come from the cache.
TEST(Cli, CvtMapElitesRunIsExactAndThreadIndependent) {
  const fs::path cache = fresh_dir("cvt_cache");
  const fs::path config = write_config("cvt", "algorithm = \"cvt-map-elites\"\n"
                                              "[cvt]\ncentroids = 200\nsamples = 4000\ninit_samples = 2000\n"
                                              "iterations = 5\ncache_dir = \"" + cache.string() + "\"\n");
  const fs::path a = fresh_dir("cvt1"), b = fresh_dir("cvt2"), c = fresh_dir("cvt3");
  const Outcome o = qdmeta_cli("run --config " + config.string() + " --out " + a.string() + " --evals 30000 --threads 1 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  EXPECT_EQ(std::distance(fs::directory_iterator(cache), fs::directory_iterator{}), 1);  // the centroids, cached
  ASSERT_EQ(qdmeta_cli("run --config " + config.string() + " --out " + b.string() + " --evals 30000 --threads 2 --quiet").status, 0);
  fs::remove_all(cache);  // made afresh with 2 threads: the same centroids
  ASSERT_EQ(qdmeta_cli("run --config " + config.string() + " --out " + c.string() + " --evals 30000 --threads 2 --quiet").status, 0);
  EXPECT_EQ(slurp(a / "metrics.csv"), slurp(b / "metrics.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(b / "archive.csv"));
  EXPECT_EQ(slurp(a / "archive.csv"), slurp(c / "archive.csv"));
  EXPECT_NE(slurp(a / "config.toml").find("centroids = 200"), std::string::npos);

  const EliteTable t = read_elites_csv(a / "archive.csv");
  ASSERT_GT(t.size(), 150);
  ASSERT_EQ(t.measures.cols(), 20);
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), 20});
    ASSERT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f)) << "row " << i;
    ASSERT_TRUE(t.measures.row(i) == t.solutions.row(i)) << "row " << i;  // descriptor = base features = genes
    ASSERT_LT(t.index[static_cast<std::size_t>(i)], 200);
  }
  std::set<std::int64_t> cells(t.index.begin(), t.index.end());
  EXPECT_EQ(static_cast<Index>(cells.size()), t.size());
}

TEST(Cli, MissingSubcommandOrOptionIsAnError) {
  EXPECT_EQ(qdmeta_cli("").status, 2);
  EXPECT_EQ(qdmeta_cli("run --out /tmp/x").status, 2);
  EXPECT_EQ(qdmeta_cli("--version").status, 0);
}

}  // namespace
}  // namespace qdmeta
