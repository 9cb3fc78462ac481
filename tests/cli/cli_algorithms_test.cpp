// Each algorithm from the command line: QD-Meta (static and SARSA control), AURORA and
// CVT-MAP-Elites store the task's fitness of each genotype and give the same bits at any thread count.
#include <gtest/gtest.h>

#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_suite.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliAlgorithms, QdMetaRunWritesMetaCsvAndTheBestMapWithBaseFeatures) {
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

TEST(CliAlgorithms, SarsaControlChoosesAndLogsGenerationsPerMetaGeneration) {
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

TEST(CliAlgorithms, AuroraRunStoresRastriginOfEachGenotypeWithLatentMeasuresAndBaseFeatures) {
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

TEST(CliAlgorithms, AuroraSameSeedSameBitsWithOneOrTwoThreads) {
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
TEST(CliAlgorithms, CvtMapElitesRunIsExactAndThreadIndependent) {
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

}  // namespace
}  // namespace qdmeta
