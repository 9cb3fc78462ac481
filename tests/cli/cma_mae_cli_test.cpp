// CMA-ME and CMA-MAE through the command line (algorithm = "cma-me" / "cma-mae"): the archive
// holds Rastrigin of each genotype, its QD-score never falls, CMA-MAE at learning rate 1 is
// CMA-ME bit for bit, a killed run resumes to the same bits, thread counts give the same bits,
// an experiment reports on them, pyribs's batch add mode runs alike, and each bad setting is one
// line naming its key.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

using cli_test::expect_same_run;
using cli_test::Outcome;
using cli_test::shell;
using cli_test::signalled_at_checkpoint;
using cli_test::slurp;

Outcome qdmeta_cli(const std::string& args) { return shell(std::string(QDMETA_BINARY) + " " + args); }

constexpr const char* kScratch = "cma_mae_cli_test";  // this process's own folder: ctest runs tests in parallel
fs::path fresh_dir(const std::string& name) { return cli_test::fresh_scratch_dir(kScratch, name); }
fs::path write_config(const std::string& name, const std::string& text) {
  return cli_test::write_scratch_config(kScratch, name, text);
}

// 20-D Rastrigin, 3 emitters of 12 (unless `emitters` says otherwise) on a 100 x 100 grid of
// genes 0 and 1; `extra` adds tables.
std::string small_config(const std::string& algorithm, std::string emitters = "", const std::string& archive = "",
                         const std::string& extra = "") {
  if (emitters.find("count =") == std::string::npos) emitters += "count = 3\n";
  if (emitters.find("batch_size =") == std::string::npos) emitters += "batch_size = 12\n";
  return "algorithm = \"" + algorithm + "\"\n[task]\nname = \"rastrigin\"\ndimensions = 20\n[emitters]\n" + emitters +
         "[archive]\n" + archive + extra;
}

Outcome run(const fs::path& config, const fs::path& out, const std::string& options = "--threads 1") {
  return qdmeta_cli("run --config " + config.string() + " --out " + out.string() + " --evals 20000 --quiet " + options);
}

std::vector<double> qd_scores(const fs::path& run_dir) {
  std::istringstream metrics(slurp(run_dir / "metrics.csv"));
  std::string line;
  std::getline(metrics, line);  // header: ..., coverage, qd_score, ...
  EXPECT_NE(line.find(",coverage,qd_score,"), std::string::npos) << line;
  std::vector<double> out;
  while (std::getline(metrics, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    out.push_back(std::stod(cells.at(6)));
  }
  return out;
}

// Every elite's objective is Rastrigin of its genes, each gene in [0, 1], one elite per cell.
void expect_rastrigin_elites(const EliteTable& t, Index cells) {
  std::set<std::int64_t> seen(t.index.begin(), t.index.end());
  EXPECT_EQ(static_cast<Index>(seen.size()), t.size());
  for (Index i = 0; i < t.size(); ++i) {
    const double f = rastrigin::standard({t.solutions.row(i).data(), 20});
    ASSERT_NEAR(t.objective[static_cast<std::size_t>(i)], f, 1e-3 + 1e-5 * std::abs(f)) << "row " << i;
    ASSERT_GE(t.solutions.row(i).minCoeff(), 0.0f) << "row " << i;
    ASSERT_LE(t.solutions.row(i).maxCoeff(), 1.0f) << "row " << i;
    ASSERT_LT(t.index[static_cast<std::size_t>(i)], cells);
  }
}

TEST(CmaMaeCli, EachAlgorithmFillsTheArchiveAndItsQdScoreNeverFalls) {
  for (const std::string algorithm : {"cma-me", "cma-mae"}) {
    const fs::path out = fresh_dir(algorithm);
    const Outcome o = run(write_config(algorithm, small_config(algorithm, "", "bins = [20, 20]\n")), out);
    ASSERT_EQ(o.status, 0) << o.output;
    const EliteTable t = read_elites_csv(out / "archive.csv");
    EXPECT_GT(t.size(), 300) << algorithm;  // of 400 cells
    expect_rastrigin_elites(t, 400);
    for (Index i = 0; i < t.size(); ++i) {  // the measures are genes 0 and 1 ([archive] measures)
      ASSERT_EQ(t.measures(i, 0), t.solutions(i, 0));
      ASSERT_EQ(t.measures(i, 1), t.solutions(i, 1));
    }
    // The archive keeps each cell's best elite whatever the learning rate: the QD-score never falls.
    const std::vector<double> qd = qd_scores(out);
    ASSERT_GT(qd.size(), 100u);
    for (std::size_t i = 1; i < qd.size(); ++i) ASSERT_GE(qd[i], qd[i - 1]) << algorithm << " row " << i;
    EXPECT_GT(qd.back(), qd[qd.size() / 10]) << algorithm;  // and still rises after the first tenth
    const std::string summary = slurp(out / "summary.json");
    EXPECT_NE(summary.find("\"algorithm\": \"" + algorithm + "\""), std::string::npos) << summary;
    EXPECT_NE(summary.find("\"evals\": 20016"), std::string::npos) << summary;  // 556 steps of 36
    EXPECT_NE(summary.find("\"emitter_restarts\""), std::string::npos) << summary;
    const std::string config = slurp(out / "config.toml");
    EXPECT_EQ(config.find("[mutation]"), std::string::npos) << "a table that does not apply was recorded";
  }
}

TEST(CmaMaeCli, CmaMaeAtLearningRateOneIsCmaMeBitForBit) {
  const fs::path me = fresh_dir("me"), mae = fresh_dir("mae1"), annealed = fresh_dir("mae001");
  const std::string me_rules =
      "ranker = \"two-stage-improvement\"\nselection_rule = \"filter\"\nrestart_rule = \"no-improvement\"\n";
  ASSERT_EQ(run(write_config("me", small_config("cma-me")), me).status, 0);
  // threshold_min defaults to the task's QD-score offset, below every Rastrigin score: with
  // alpha 1 each threshold is then the cell's best, as CMA-ME's, and the two-stage ranker
  // orders new cells the same whatever threshold_min is.
  const Outcome o = run(write_config("mae1", small_config("cma-mae", me_rules, "learning_rate = 1.0\n")), mae);
  ASSERT_EQ(o.status, 0) << o.output;
  expect_same_run(me, mae);
  // The learning rate is read: at 0.01 the same rules give another archive.
  ASSERT_EQ(run(write_config("mae001", small_config("cma-mae", me_rules, "learning_rate = 0.01\n")), annealed).status, 0);
  EXPECT_NE(slurp(me / "archive.csv"), slurp(annealed / "archive.csv"));
}

TEST(CmaMaeCli, SameBitsWithOneOrTwoThreadsAndFromTheResolvedConfig) {
  for (const std::string algorithm : {"cma-me", "cma-mae"}) {
    const fs::path config = write_config("threads-" + algorithm, small_config(algorithm));
    const fs::path one = fresh_dir("one-" + algorithm), two = fresh_dir("two-" + algorithm),
                   again = fresh_dir("again-" + algorithm);
    ASSERT_EQ(run(config, one, "--threads 1").status, 0);
    ASSERT_EQ(run(config, two, "--threads 2").status, 0);
    expect_same_run(one, two);
    const Outcome o = run(one / "config.toml", again, "--threads 2");
    ASSERT_EQ(o.status, 0) << o.output;
    expect_same_run(one, again);
  }
}

TEST(CmaMaeCli, AKilledRunResumesToTheSameBits) {
  const std::string every_step = "[checkpoint]\nevery_seconds = 0\n";
  const std::vector<std::pair<std::string, std::string>> configs = {
      {"resume-me", small_config("cma-me", "", "", every_step)},
      {"resume-mae", small_config("cma-mae", "restart_rule = \"every-n\"\nrestart_every = 7\n", "learning_rate = 0.1\n",
                                  every_step)}};
  for (const auto& [name, text] : configs) {
    const fs::path config = write_config(name, text);
    const fs::path straight = fresh_dir(name + "-straight"), killed = fresh_dir(name + "-killed");
    ASSERT_EQ(run(config, straight).status, 0);
    // SIGKILL after the 200th checkpoint (step 200 of 556): the emitters are mid-flight.
    signalled_at_checkpoint(std::string(QDMETA_BINARY) + " run --config " + config.string() + " --out " +
                                killed.string() + " --evals 20000 --quiet --threads 1",
                            200, "KILL");
    ASSERT_TRUE(fs::exists(killed / "checkpoint.bin")) << name;
    ASSERT_FALSE(fs::exists(killed / "summary.json")) << name << " finished before it was killed";
    const Outcome r = qdmeta_cli("resume --out " + killed.string() + " --threads 2");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("resuming from checkpoint"), std::string::npos) << r.output;
    expect_same_run(straight, killed);
  }
}

// Runs `config` (20,000 evaluations) on one thread into `one`, on two, and killed after its
// `checkpoint`-th checkpoint and resumed on two: the three give the same bits.
void expect_thread_independent_and_resumable(const fs::path& config, const std::string& name, int checkpoint,
                                             const fs::path& one) {
  const fs::path two = fresh_dir(name + "-two"), killed = fresh_dir(name + "-killed");
  const Outcome o = run(config, one);
  ASSERT_EQ(o.status, 0) << o.output;
  ASSERT_EQ(run(config, two, "--threads 2").status, 0);
  expect_same_run(one, two);
  signalled_at_checkpoint(std::string(QDMETA_BINARY) + " run --config " + config.string() + " --out " + killed.string() +
                              " --evals 20000 --quiet --threads 1",
                          checkpoint, "KILL");
  ASSERT_TRUE(fs::exists(killed / "checkpoint.bin"));
  ASSERT_FALSE(fs::exists(killed / "summary.json")) << name << " finished before it was killed";
  ASSERT_EQ(qdmeta_cli("resume --out " + killed.string() + " --threads 2 --quiet").status, 0);
  expect_same_run(one, killed);
}

// QD-Meta over CMA-MAE (qd_meta.bottom_level = "cma-mae"), killed after its 20th meta-generation;
// and the same over Gaussian emitters ([emitters] kind = "gaussian").
TEST(CmaMaeCli, QdMetaOverCmaMaeIsThreadIndependentAndResumesToTheSameBits) {
  for (const std::string kind : {"", "kind = \"gaussian\"\nsigma = 0.05\n"}) {
    const std::string name = kind.empty() ? "qdm" : "qdm-gaussian";
    const fs::path config = write_config(
        name, "algorithm = \"qd-meta\"\n[task]\nname = \"rastrigin\"\ndimensions = 20\n[qd_meta]\nbottom_level = \"cma-mae\"\n"
              "meta_population = 3\ninitial_population = 200\n[emitters]\n" + kind + "count = 4\nbatch_size = 10\n[control]\n"
              "kind = \"static\"\ngenerations = 2\n[archive]\nbins = [20, 20]\n[checkpoint]\nevery_seconds = 0\n");
    const fs::path one = fresh_dir(name + "-one");
    expect_thread_independent_and_resumable(config, name, 20, one);
    EXPECT_GT(read_elites_csv(one / "archive.csv").size(), 150) << name;  // of 400 cells
  }
}

// es = "sep-cma-es": the separable CMA-ES in every emitter fills the archive with true Rastrigin
// elites, gives the same bits on one thread and two, and a killed run resumes to them.
TEST(CmaMaeCli, SeparableEsRunIsThreadIndependentAndResumesToTheSameBits) {
  const fs::path config = write_config(
      "sep", small_config("cma-mae", "es = \"sep-cma-es\"\n", "bins = [20, 20]\n", "[checkpoint]\nevery_seconds = 0\n"));
  const fs::path one = fresh_dir("sep-one");
  expect_thread_independent_and_resumable(config, "sep", 200, one);
  const EliteTable t = read_elites_csv(one / "archive.csv");
  EXPECT_GT(t.size(), 200);  // of 400 cells
  expect_rastrigin_elites(t, 400);
  EXPECT_NE(slurp(one / "config.toml").find("es = 'sep-cma-es'"), std::string::npos);
}

// [emitters] add_mode = "batch" (pyribs's): CMA-MAE and QD-Meta over it give the same bits on one
// thread and two, a killed run resumes to them, the resolved config keeps the mode, and the run
// is not the single mode's.
TEST(CmaMaeCli, BatchAddModeIsThreadIndependentResumableAndNotTheSingleMode) {
  const std::string mode = "add_mode = \"batch\"\n";
  const std::string checkpoints = "[checkpoint]\nevery_seconds = 0\n";
  const fs::path config = write_config("batch", small_config("cma-mae", mode, "bins = [20, 20]\n", checkpoints));
  const fs::path one = fresh_dir("batch-one"), single = fresh_dir("batch-single");
  expect_thread_independent_and_resumable(config, "batch", 200, one);
  expect_rastrigin_elites(read_elites_csv(one / "archive.csv"), 400);
  EXPECT_NE(slurp(one / "config.toml").find("add_mode = 'batch'"), std::string::npos);
  ASSERT_EQ(run(write_config("batch-single", small_config("cma-mae", "", "bins = [20, 20]\n")), single).status, 0);
  EXPECT_EQ(slurp(single / "config.toml").find("add_mode"), std::string::npos);  // written only when given
  EXPECT_NE(slurp(one / "archive.csv"), slurp(single / "archive.csv"));

  const fs::path qdm = write_config(
      "qdm-batch", "algorithm = \"qd-meta\"\n[task]\nname = \"rastrigin\"\ndimensions = 20\n[qd_meta]\nbottom_level = "
                   "\"cma-mae\"\nmeta_population = 3\ninitial_population = 200\n[emitters]\n" + mode + "count = 4\n"
                   "batch_size = 10\n[control]\nkind = \"static\"\ngenerations = 2\n[archive]\nbins = [20, 20]\n" + checkpoints);
  const fs::path qdm_one = fresh_dir("qdm-batch-one");
  expect_thread_independent_and_resumable(qdm, "qdm-batch", 20, qdm_one);
  EXPECT_GT(read_elites_csv(qdm_one / "archive.csv").size(), 150);  // of 400 cells
}

// [emitters] kind = "gaussian" / "iso-line": MAP-Elites's variation as emitters under CMA-ME's
// scheduler fills the archive with true Rastrigin elites in [0, 1], reports no restarts, gives
// the same bits on one thread and two, and (Gaussian) a killed run resumes to them.
TEST(CmaMaeCli, GaussianAndIsoLineEmittersFillTheArchiveThreadIndependently) {
  const fs::path gaussian = write_config(
      "gaussian", small_config("cma-me", "kind = \"gaussian\"\nsigma = 0.05\n", "bins = [20, 20]\n",
                               "[checkpoint]\nevery_seconds = 0\n"));
  const fs::path one = fresh_dir("gaussian-one");
  expect_thread_independent_and_resumable(gaussian, "gaussian", 200, one);
  const fs::path iso = write_config(
      "iso", small_config("cma-me", "kind = \"iso-line\"\niso_sigma = 0.02\nline_sigma = 0.3\n", "bins = [20, 20]\n"));
  const fs::path iso_one = fresh_dir("iso-one"), iso_two = fresh_dir("iso-two");
  ASSERT_EQ(run(iso, iso_one, "--threads 1").status, 0);
  ASSERT_EQ(run(iso, iso_two, "--threads 2").status, 0);
  expect_same_run(iso_one, iso_two);
  for (const fs::path& dir : {one, iso_one}) {
    const EliteTable t = read_elites_csv(dir / "archive.csv");
    EXPECT_GT(t.size(), 200) << dir;  // of 400 cells
    expect_rastrigin_elites(t, 400);
    EXPECT_NE(slurp(dir / "summary.json").find("\"emitter_restarts\": 0"), std::string::npos) << dir;
    const std::vector<double> scores = qd_scores(dir);
    EXPECT_TRUE(std::is_sorted(scores.begin(), scores.end())) << dir;
  }
  EXPECT_NE(slurp(one / "config.toml").find("kind = 'gaussian'"), std::string::npos);
  EXPECT_EQ(slurp(one / "config.toml").find("sigma0"), std::string::npos);  // not a Gaussian emitter's key
}

// CVT cells (200 centroids, made once and cached): each elite's cell is its own, its measures
// its genes (Rastrigin's base features), and resuming or a second thread changes no bit.
TEST(CmaMaeCli, CvtArchiveRunIsExactResumableAndThreadIndependent) {
  const fs::path cache = fresh_dir("cvt-cache");
  const fs::path config = write_config(
      "cvt", small_config("cma-mae", "", "kind = \"cvt\"\n",
                          "[cvt]\ncentroids = 200\nsamples = 4000\ninit_samples = 2000\niterations = 5\ncache_dir = \"" +
                              cache.string() + "\"\n[checkpoint]\nevery_seconds = 0\n"));
  const fs::path one = fresh_dir("cvt-one");
  expect_thread_independent_and_resumable(config, "cvt", 100, one);

  const EliteTable t = read_elites_csv(one / "archive.csv");
  EXPECT_GT(t.size(), 150);
  ASSERT_EQ(t.measures.cols(), 20);
  expect_rastrigin_elites(t, 200);
  for (Index i = 0; i < t.size(); ++i) ASSERT_TRUE(t.measures.row(i) == t.solutions.row(i)) << "row " << i;
}

TEST(CmaMaeCli, AnExperimentOfBothReportsAndPlotsThem) {
  const fs::path me = write_config("exp-me", small_config("cma-me"));
  const fs::path mae = write_config("exp-mae", small_config("cma-mae"));
  const fs::path experiment = write_config(
      "experiment", "name = \"emitters\"\nreplicates = 2\ntests = [\"dimension\"]\n[[condition]]\nname = \"CMA-ME\"\n"
                    "config = \"" + me.string() + "\"\n[[condition]]\nname = \"CMA-MAE\"\nconfig = \"" + mae.string() + "\"\n");
  const fs::path out = fresh_dir("experiment");
  const Outcome o = qdmeta_cli("experiment --config " + experiment.string() + " --out " + out.string() + " --evals 10000");
  ASSERT_EQ(o.status, 0) << o.output;
  for (const char* run_dir : {"cma-me/seed-1", "cma-me/seed-2", "cma-mae/seed-1", "cma-mae/seed-2"})
    for (const char* file : {"summary.json", "archive.csv", "metrics.csv"})
      EXPECT_TRUE(fs::exists(out / run_dir / file)) << run_dir << "/" << file;
  const std::string report = slurp(out / "report.md");
  EXPECT_NE(report.find("| CMA-ME | 2 | "), std::string::npos) << report;
  EXPECT_NE(report.find("| CMA-MAE | 2 | "), std::string::npos) << report;
  for (const char* figure : {"archives.png", "qd-statistics.png", "adaptation-dimension.png"})
    EXPECT_TRUE(fs::exists(out / "figures" / figure)) << figure;
}

TEST(CmaMaeCli, BadSettingsAreOneLineNamingTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {small_config("cma-mae", "", "learning_rate = 1.5\n"), "archive.learning_rate = 1.5 is out of range: must be in [0, 1]"},
      {small_config("cma-mae", "", "learning_rate = -0.01\n"), "archive.learning_rate = -0.01 is out of range: must be in [0, 1]"},
      {small_config("cma-mae", "", "threshold_min = -inf\n"), "archive.threshold_min = -inf is out of range: must be finite"},
      {small_config("cma-me", "", "learning_rate = 0.5\n"),
       "archive.learning_rate does not apply to algorithm \"cma-me\" (learning rate 1, threshold_min -inf): use "
       "algorithm = \"cma-mae\""},
      {small_config("cma-me", "", "threshold_min = 0\n"), "archive.threshold_min does not apply to algorithm \"cma-me\""},
      {small_config("cma-me", "count = 0\n"), "emitters.count = 0 is out of range: must be in [1, 10000]"},
      {small_config("cma-me", "batch_size = 0\n"), "emitters.batch_size = 0 is out of range: must be in [1, 1000000]"},
      {small_config("cma-mae", "sigma0 = 0\n"), "emitters.sigma0 = 0 is out of range: must be > 0"},
      {small_config("cma-mae", "sigma0 = -0.5\n"), "emitters.sigma0 = -0.5 is out of range: must be > 0"},
      {small_config("cma-me", "x0 = 1.5\n"), "emitters.x0 = 1.5 is out of range: must be in [0, 1]"},
      {small_config("cma-me", "ranker = \"2imp\"\n"),
       "emitters.ranker = \"2imp\" is not a valid choice: use one of \"improvement\", \"two-stage-improvement\", "
       "\"objective\", \"two-stage-objective\", \"random-direction\", \"two-stage-random-direction\""},
      {small_config("cma-mae", "add_mode = \"batches\"\n"),
       "emitters.add_mode = \"batches\" is not a valid choice: use one of \"single\", \"batch\""},
      {small_config("cma-me", "selection_rule = \"best\"\n"),
       "emitters.selection_rule = \"best\" is not a valid choice: use one of \"filter\", \"mu\""},
      {small_config("cma-me", "restart_rule = \"never\"\n"),
       "emitters.restart_rule = \"never\" is not a valid choice: use one of \"no-improvement\", \"basic\", \"every-n\""},
      {small_config("cma-me", "restart_rule = \"every-n\"\nrestart_every = 0\n"),
       "emitters.restart_every = 0 is out of range: must be in [1, 1000000000]"},
      {small_config("cma-me", "restart_every = 5\n"),
       "emitters.restart_every applies only to restart_rule = \"every-n\" (here \"no-improvement\")"},
      {small_config("cma-me", "bounds = \"none\"\n"),
       "emitters.bounds = \"none\" is not a valid choice: use one of \"resample\", \"clamp\""},
      {small_config("cma-me", "es = \"sep_cma_es\"\n"),
       "emitters.es = \"sep_cma_es\" is not a valid choice: use one of \"cma-es\", \"sep-cma-es\""},
      {small_config("cma-me", "kind = \"novelty\"\n"),
       "emitters.kind = \"novelty\" is not a valid choice: use one of \"evolution-strategy\", \"gaussian\", \"iso-line\""},
      {small_config("cma-me", "kind = \"gaussian\"\nsigma = 0\n"), "emitters.sigma = 0 is out of range: must be > 0"},
      {small_config("cma-me", "kind = \"gaussian\"\nsigma = -0.1\n"), "emitters.sigma = -0.1 is out of range: must be > 0"},
      {small_config("cma-mae", "kind = \"iso-line\"\niso_sigma = -0.01\n"),
       "emitters.iso_sigma = -0.01 is out of range: must be >= 0"},
      {small_config("cma-mae", "kind = \"iso-line\"\nline_sigma = -1\n"),
       "emitters.line_sigma = -1 is out of range: must be >= 0"},
      {small_config("cma-me", "kind = \"gaussian\"\nsigma0 = 0.2\n"),
       "emitters.sigma0 applies only to kind = \"evolution-strategy\" (here \"gaussian\")"},
      {small_config("cma-me", "kind = \"iso-line\"\nes = \"sep-cma-es\"\n"),
       "emitters.es applies only to kind = \"evolution-strategy\" (here \"iso-line\")"},
      {small_config("cma-me", "kind = \"iso-line\"\nsigma = 0.1\n"),
       "emitters.sigma applies only to kind = \"gaussian\" (here \"iso-line\")"},
      {small_config("cma-me", "line_sigma = 0.1\n"),
       "emitters.line_sigma applies only to kind = \"iso-line\" (here \"evolution-strategy\")"},
      {small_config("cma-me", "counts = 2\n"), "unknown key 'emitters.counts' in [emitters]"},
      {small_config("cma-me", "", "kind = \"proximity\"\n"),
       "archive.kind = \"proximity\" is not a valid choice: use one of \"grid\", \"cvt\""},
      {small_config("cma-me", "", "kind = \"cvt\"\nbins = [5, 5]\n"), "unknown key 'archive.bins' in [archive]"},
      {small_config("cma-me", "", "", "[mutation]\nkind = \"gaussian\"\n"),
       "[mutation] does not apply to algorithm \"cma-me\": its emitters' CMA-ES make each batch ([emitters])"},
      {small_config("cma-mae", "", "", "[map_elites]\nbatch_size = 10\n"),
       "[map_elites] does not apply to algorithm \"cma-mae\""},
      {small_config("cma-me", "", "", "[cvt]\ncentroids = 10\n"), "[cvt] does not apply to algorithm \"cma-me\""},
      {small_config("cma-me", "", "kind = \"cvt\"\n", "[feature_map]\nkind = \"select\"\n"),
       "[feature_map] does not apply to algorithm \"cma-me\": with archive.kind = \"cvt\""},
  };
  const fs::path out = fresh_dir("refused");
  for (const auto& [text, message] : cases) {
    const fs::path config = write_config("bad", text);
    const Outcome o = run(config, out);
    EXPECT_EQ(o.status, 2) << text;
    EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
    EXPECT_NE(o.output.find(config.string() + ": " + message), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(out)) << "a refused config made its run directory";
  }
}

}  // namespace
}  // namespace qdmeta
