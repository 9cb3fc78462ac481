// The command line on the RHex task: a tiny QD-Meta Damage run ends, writes the contracted files,
// stores fitness equal to a fresh episode of the stored genotype, and gives the same bits with 1
// and 2 threads.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_helpers.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

int run_cli(const std::string& args, std::string* output = nullptr) {
  const cli_test::Outcome o = cli_test::shell(std::string(QDMETA_BINARY) + " " + args);
  if (output) *output = o.output;
  return o.status;
}

using cli_test::slurp;

// This process's own scratch folder (ctest runs tests as parallel processes, and two suites may
// run at once): never a fixed name under TMPDIR.
fs::path scratch() { return cli_test::process_scratch("rhex_cli"); }

// smoke-damage.toml made smaller still: 0.5 s episodes, 8 random genotypes, 4 offspring, 1 generation.
fs::path tiny_config(const std::string& name = "tiny") {
  std::string text = slurp(std::string(QDMETA_SOURCE_DIR) + "/configs/rhex/smoke-damage.toml");
  auto set = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  set("evaluations = 1_000", "evaluations = 20");
  set("episode_seconds = 1.0", "episode_seconds = 0.5");
  set("settle_steps = 300", "settle_steps = 100");
  set("batch_size = 16", "batch_size = 4");
  set("initial_population = 64", "initial_population = 8");
  set("generations = 2", "generations = 1");
  const fs::path path = scratch() / (name + ".toml");
  std::ofstream(path) << text;
  return path;
}

TEST(RhexCli, TinyQdMetaDamageRun) {
  const fs::path config = tiny_config();
  std::array<fs::path, 2> outs;
  for (int threads : {1, 2}) {
    const fs::path out = scratch() / ("threads" + std::to_string(threads));
    fs::remove_all(out);
    std::string output;
    ASSERT_EQ(run_cli("run --config " + config.string() + " --out " + out.string() + " --quiet --threads " +
                          std::to_string(threads),
                      &output),
              0)
        << output;
    for (const char* f : {"config.toml", "metrics.csv", "meta.csv", "archive.csv", "summary.json"})
      EXPECT_TRUE(fs::exists(out / f)) << f;
    outs[static_cast<std::size_t>(threads - 1)] = out;
  }
  EXPECT_EQ(slurp(outs[0] / "archive.csv"), slurp(outs[1] / "archive.csv"));
  EXPECT_EQ(slurp(outs[0] / "metrics.csv"), slurp(outs[1] / "metrics.csv"));
  EXPECT_NE(slurp(outs[0] / "config.toml").find("damage_types = ["), std::string::npos);

  // Stored fitness = a fresh episode of the stored genotype with the run's task settings.
  const EliteTable t = read_elites_csv(outs[0] / "archive.csv");
  ASSERT_GT(t.size(), 0);
  RhexParams p;
  p.features = RhexFeatures::kFeatureSets;
  p.episode.duration = 0.5;
  p.episode.settle_steps = 100;
  const RhexTask task(p);
  for (Index i = 0; i < std::min<Index>(t.size(), 3); ++i) {
    std::array<Real, rhex::kGenes> g{};
    for (int j = 0; j < rhex::kGenes; ++j) g[j] = t.solutions(i, j);
    const auto r = task.episode(g.data(), {});
    ASSERT_FALSE(r.dead);
    EXPECT_NEAR(t.objective[i], r.fitness, 1e-3 + 1e-5 * std::abs(r.fitness));
  }
}

// The test phase from the command line: the tiny run trained on 1 damage type, so its damage
// test is the other 3 types x 6 legs; 2 evaluations each (36 half-second episodes). Then the
// generalisation table on a one-solution archive (33 episodes).
TEST(RhexCli, AdaptWritesTheDamageCurveAndTheGeneralisationTable) {
  const fs::path config = tiny_config("adapt");
  const fs::path out = scratch() / "adapt";
  fs::remove_all(out);
  std::string output;
  ASSERT_EQ(run_cli("run --config " + config.string() + " --out " + out.string() + " --quiet --threads 2", &output), 0)
      << output;
  ASSERT_EQ(run_cli("adapt --run " + out.string() + " --test damage --budget 2 --threads 2", &output), 0) << output;
  EXPECT_NE(output.find("18 functions x 2 evaluations"), std::string::npos) << output;
  std::istringstream curve(slurp(out / "adapt-damage.csv"));
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(curve, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], "evaluations,best_mean,best_se");
  EXPECT_TRUE(rows[1].starts_with("1,")) << rows[1];
  EXPECT_TRUE(rows[2].starts_with("2,")) << rows[2];
  const double first = std::stod(rows[1].substr(2)), last = std::stod(rows[2].substr(2));
  EXPECT_GE(last, first);  // best so far
  EXPECT_LT(last, 5.0);    // metres in half a second: a distance, not a sum

  ASSERT_EQ(run_cli("adapt --run " + out.string() + " --test walk", &output), 2);
  EXPECT_NE(output.find("valid tests are damage, obstacle, damage-training, obstacle-training, generalisation"),
            std::string::npos)
      << output;

  // Keep three solutions so that the tables stay cheap; score one of them, drawn from the seed.
  std::istringstream archive(slurp(out / "archive.csv"));
  std::string header, row;
  std::getline(archive, header);
  std::string kept = header + "\n";
  for (int i = 0; i < 3 && std::getline(archive, row); ++i) kept += row + "\n";
  std::ofstream(out / "archive.csv") << kept;
  ASSERT_EQ(run_cli("adapt --run " + out.string() + " --test generalisation --solutions 1 --threads 2", &output), 0)
      << output;
  EXPECT_NE(output.find("1 of 3 archive solutions"), std::string::npos) << output;
  const std::string drawn = slurp(out / "generalisation.csv");
  ASSERT_EQ(run_cli("adapt --run " + out.string() + " --test generalisation --solutions 1 --threads 1 --quiet", &output),
            0);
  EXPECT_EQ(slurp(out / "generalisation.csv"), drawn);  // the same draw, at any thread count
  EXPECT_EQ(run_cli("adapt --run " + out.string() + " --test damage --solutions 1", &output), 2) << output;
  std::istringstream table(slurp(out / "generalisation.csv"));
  rows.clear();
  while (std::getline(table, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0], "group,environments,solutions,mean,se");
  EXPECT_TRUE(rows[1].starts_with("damage-training,6,1,")) << rows[1];
  EXPECT_TRUE(rows[2].starts_with("obstacle-training,5,1,")) << rows[2];
  EXPECT_TRUE(rows[3].starts_with("damage,18,1,")) << rows[3];
  EXPECT_TRUE(rows[4].starts_with("obstacle,4,1,")) << rows[4];
  EXPECT_EQ(run_cli("adapt --run " + out.string() + " --test generalisation --budget 3", &output), 2) << output;
}

// The cluster path (scripts/slurm-experiment.sh): `qdmeta run` of planned runs, seed by seed,
// then the experiment again. RHex draws its damage types from the seed, so a run's config at its
// own seed differs from its condition at seed 1; what it records must still be the condition's
// fingerprint, or the experiment refuses its own planned runs.
TEST(RhexCli, PlannedRunsOfSeedDrawnDamageTypesAreTheConditionsOwn) {
  const fs::path config = tiny_config("planned");
  const fs::path dir = scratch() / "planned";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "experiment.toml") << "name = \"planned\"\nreplicates = 3\n[[condition]]\nname = \"damage\"\n"
                                            "config = \"" << config.string() << "\"\n";
  const std::string plan = "experiment --plan --quiet --config " + (dir / "experiment.toml").string() + " --out " +
                           (dir / "out").string();
  std::string output;
  ASSERT_EQ(run_cli(plan, &output), 0) << output;
  std::set<std::string> draws;
  for (int seed = 1; seed <= 3; ++seed) {
    const fs::path run = dir / "out" / "damage" / ("seed-" + std::to_string(seed));
    ASSERT_EQ(run_cli("run --quiet --threads 1 --config " + (dir / "out" / "damage" / "condition.toml").string() +
                          " --seed " + std::to_string(seed) + " --out " + run.string(),
                      &output),
              0)
        << output;
    const std::string resolved = slurp(run / "config.toml");
    const auto at = resolved.find("damage_types = ");
    ASSERT_NE(at, std::string::npos);
    draws.insert(resolved.substr(at, resolved.find('\n', at) - at));
  }
  ASSERT_GT(draws.size(), 1u) << "the seeds drew the same damage types: the test would not cover the case";
  EXPECT_EQ(run_cli(plan, &output), 0) << output;  // refused as "run with another config" before
}

}  // namespace
}  // namespace qdmeta

