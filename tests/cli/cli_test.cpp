// The command line end to end: the files and columns DESIGN.md promises, exit status 2 with a
// one-line message on bad input, refusal to overwrite, and the same bits at any thread count.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;
  std::string output;  // stdout and stderr together
};

Outcome qdmeta_cli(const std::string& args) {
  const std::string command = std::string(QDMETA_BINARY) + " " + args + " 2>&1";
  Outcome o;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return o;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) o.output += buffer;
  const int raw = pclose(pipe);
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return o;
}

std::string config_path() { return std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml"; }

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("qdmeta_cli_test_" + name);
  fs::remove_all(dir);
  return dir;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path write_config(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("qdmeta_cli_test_" + name + ".toml");
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
  const std::string config = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/qdmeta-translation.toml";
  const Outcome o = qdmeta_cli("run --config " + config + " --out " + a.string() + " --evals 60000 --threads 1 --quiet");
  ASSERT_EQ(o.status, 0) << o.output;
  ASSERT_EQ(qdmeta_cli("run --config " + config + " --out " + b.string() + " --evals 60000 --threads 2 --quiet").status, 0);
  const std::string meta = slurp(a / "meta.csv");
  EXPECT_TRUE(meta.starts_with("meta_generation,evals,evals_bottom,evals_meta,meta_fitness_best,meta_fitness_mean,"
                               "meta_fitness_sd,generations,states\n"));
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
