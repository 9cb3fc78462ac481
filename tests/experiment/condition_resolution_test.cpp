// Resolving a condition (experiment/kept_runs.hpp) reads its config and makes nothing: every
// shipped config's resolved-config fingerprint and budget against the values the code printed
// when conditions were resolved by building them (tests/data/condition_fingerprints.tsv: the plan.tsv
// fingerprints and condition.toml budgets of `qdmeta experiment --plan` at b0d6058, each run config
// planned as a one-condition experiment), so that no fingerprint a run directory, a kept summary
// or a plan.tsv row already holds changes; the resolved path against the building one on each
// shipped config; and a plan of several conditions that makes no task.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "expect_input_error.hpp"
#include "own_temp_path.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/experiment/experiment.hpp"
#include "qdmeta/experiment/kept_runs.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

const fs::path kSource = QDMETA_SOURCE_DIR;
const fs::path kGolden = kSource / "tests/data/condition_fingerprints.tsv";

// configs/<task>/ files, sorted; experiment files are those with [[condition]] tables.
std::vector<fs::path> shipped_configs() {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(kSource / "configs"))
    if (e.is_regular_file() && e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

bool built_here(const fs::path& relative) {
#ifdef QDMETA_TEST_RHEX
  (void)relative;
  return true;
#else
  return !relative.string().starts_with("configs/rhex/");
#endif
}

// One line per run config (resolved as a condition is, at its own budget) and per condition of
// each experiment file: file, condition slug ("-" for a run config), budget, fingerprint.
std::string resolved_listing() {
  std::ostringstream out;
  for (const fs::path& file : shipped_configs()) {
    const fs::path relative = fs::relative(file, kSource);
    if (!built_here(relative)) continue;
    const toml::table config = load_toml(file);
    if (!config.contains("condition")) {
      const ResolvedCondition r = resolve_condition(config, file.string(), std::nullopt);
      out << relative.string() << "\t-\t" << r.budget << '\t' << r.fingerprint << '\n';
      continue;
    }
    const ExperimentSpec spec = load_experiment(file, std::nullopt, std::nullopt);
    const std::vector<ResolvedCondition> resolved = resolve_conditions(spec);
    for (std::size_t i = 0; i < resolved.size(); ++i)
      out << relative.string() << '\t' << spec.conditions[i].slug << '\t' << resolved[i].budget << '\t'
          << resolved[i].fingerprint << '\n';
  }
  return out.str();
}

// The golden's lines for the configs this build has (the RHex task's need it).
std::string golden_listing() {
  std::ifstream in(kGolden);
  std::ostringstream out;
  for (std::string line; std::getline(in, line);)
    if (built_here(line.substr(0, line.find('\t')))) out << line << '\n';
  return out.str();
}

TEST(ConditionResolution, ShippedConfigsKeepTheFingerprintsAndBudgetsTheyHadWhenBuilt) {
  register_builtin_plugins();
  const std::string listing = resolved_listing();
  if (std::getenv("QDMETA_RECORD_CONDITION_FINGERPRINTS") != nullptr) {  // how the golden was made
    std::ofstream(kGolden) << listing;
    GTEST_SKIP() << "recorded " << kGolden.string();
  }
  ASSERT_TRUE(fs::is_regular_file(kGolden));
  EXPECT_FALSE(listing.empty());
  EXPECT_EQ(listing, golden_listing());
}

// Resolving (BuildScope::kResolve) against building the tasks (kTasksOnly) on each shipped run
// config: the same resolved table, budget, memory estimate and task shape.
TEST(ConditionResolution, ResolvingReadsWhatBuildingReads) {
  register_builtin_plugins();
  int compared = 0;
  for (const fs::path& file : shipped_configs()) {
    if (!built_here(fs::relative(file, kSource))) continue;
    const toml::table config = load_toml(file);
    if (config.contains("condition")) continue;
    for (const std::uint64_t seed : {1, 3}) {  // RHex draws its damage types from the seed
      const BuiltRun built = build_run(config, file.string(), {seed, std::nullopt}, BuildScope::kTasksOnly);
      const BuiltRun resolved = build_run(config, file.string(), {seed, std::nullopt}, BuildScope::kResolve);
      EXPECT_EQ(resolved.resolved, built.resolved) << file;
      EXPECT_EQ(resolved.settings.budget, built.settings.budget) << file;
      EXPECT_EQ(resolved.settings.fingerprint, built.settings.fingerprint) << file;
      EXPECT_EQ(resolved.memory.total(), built.memory.total()) << file;
      ASSERT_FALSE(resolved.evaluation_tasks.empty());
      EXPECT_EQ(shape_of(resolved.evaluation_tasks.front()), shape_of(built.evaluation_tasks.front())) << file;
      ++compared;
    }
  }
  EXPECT_GE(compared, 2 * 10);
}

// What making a task or meta-objective refuses, resolving refuses in the same words (their checks
// run without the objects).
TEST(ConditionResolution, ResolvingRefusesWhatMakingRefuses) {
  register_builtin_plugins();
  std::vector<std::string> configs = {
      "algorithm = \"qd-meta\"\n[meta_fitness]\nkind = \"dimension\"\ndimension_count = 2\ndimensions = [3, 3]\n",
      "[task]\ndimensions = 0\n",
  };
#ifdef QDMETA_TEST_RHEX
  configs.push_back("[task]\nname = \"rhex\"\ndamage = \"leg-removal\"\ncourse = \"stairs\"\n");
  configs.push_back("algorithm = \"qd-meta\"\n[task]\nname = \"rhex\"\n[meta_fitness]\nsample_fraction = 0\n");
#endif
  for (const std::string& text : configs) {
    const toml::table config = toml::parse(text);
    const std::string made = input_error_message([&] { build_run(config, "c.toml", {}, BuildScope::kTasksOnly); });
    EXPECT_FALSE(made.empty()) << text;
    EXPECT_EQ(input_error_message([&] { build_run(config, "c.toml", {}, BuildScope::kResolve); }), made) << text;
  }
}

// A task whose every construction (copies included) is counted.
struct CountedTask {
  static inline int made = 0;
  Index genes = 2;
  explicit CountedTask(Index n) : genes(n) { ++made; }
  CountedTask(const CountedTask& other) : genes(other.genes) { ++made; }
  std::string name() const { return "counted"; }
  Index genotype_size() const { return genes; }
  Index base_feature_size() const { return 2; }
  void evaluate(GenotypeView, EvaluationView) const {}
};

void register_counted_task() {
  TaskPlugin plugin;
  const auto genes = [](ConfigReader& t) { return t.integer("genes", 2, 2, 1000); };
  plugin.read_task = [genes](ConfigReader& t) { return Task(CountedTask(genes(t))); };
  plugin.read_shape = [genes](ConfigReader& t) { return TaskShape{"counted", genes(t), 2, 0.0}; };
  register_task_plugin("counted", std::move(plugin));
}

TEST(ConditionResolution, PlanningSeveralConditionsMakesNoTask) {
  register_builtin_plugins();
  register_counted_task();
  const fs::path dir = test::own_temp_path("condition_resolution");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "run.toml") << "[task]\nname = \"counted\"\ngenes = 4\n[budget]\nevaluations = 500\n";
  std::ofstream(dir / "experiment.toml") << R"(name = "counted"
replicates = 2
[[condition]]
name = "MAP-Elites"
config = "run.toml"
[[condition]]
name = "CVT-MAP-Elites"
config = "run.toml"
set = { algorithm = "cvt-map-elites", cvt = { centroids = 20, samples = 200 } }
[[condition]]
name = "AURORA"
config = "run.toml"
set = { algorithm = "aurora", task = { genes = 6 } }
[[condition]]
name = "CMA-MAE"
config = "run.toml"
set = { algorithm = "cma-mae", budget = { evaluations = 900 } }
)";
  const ExperimentSpec spec = load_experiment(dir / "experiment.toml", std::nullopt, std::nullopt);
  CountedTask::made = 0;
  const std::vector<ResolvedCondition> resolved = resolve_conditions(spec);
  write_experiment_plan(spec, dir / "out", {});
  EXPECT_EQ(CountedTask::made, 0) << "resolving or planning made the task";
  ASSERT_EQ(resolved.size(), 4u);
  EXPECT_EQ(resolved[0].budget, 500);
  EXPECT_EQ(resolved[3].budget, 900);
  // The plan's fingerprints are those of the conditions built (which makes the tasks, counted).
  std::ifstream plan(dir / "out/plan.tsv");
  std::string text((std::istreambuf_iterator<char>(plan)), std::istreambuf_iterator<char>());
  for (std::size_t i = 0; i < spec.conditions.size(); ++i) {
    const BuiltRun built = build_run(spec.conditions[i].effective_config(), "built", {1, std::nullopt},
                                     BuildScope::kTasksOnly);
    const std::string fingerprint = resolved_config_fingerprint(built.resolved);
    EXPECT_EQ(resolved[i].fingerprint, fingerprint) << spec.conditions[i].name;
    EXPECT_NE(text.find(spec.conditions[i].slug + "\t1\t"), std::string::npos);
    EXPECT_NE(text.find("\t" + fingerprint + "\n"), std::string::npos) << text;
  }
  EXPECT_GT(CountedTask::made, 0);
  // Planned again over two kept runs, one of its condition's config (fingerprint stored) and one
  // of an older config with no fingerprint (started over with --restart-changed): the kept runs
  // and plan.tsv's rows are checked by resolving, and no task is made.
  for (const auto& [seed, genes] : {std::pair{1, 4}, std::pair{2, 8}}) {
    toml::table run = build_run(spec.conditions[0].effective_config(), "run", {seed, std::nullopt}, BuildScope::kResolve)
                          .resolved;
    run.insert_or_assign("task", toml::table{{"name", "counted"}, {"genes", genes}});
    if (seed == 1) run.insert("provenance", toml::table{{kConfigFingerprintKey, resolved[0].fingerprint}});
    fs::create_directories(replicate_dir(dir / "out", spec.conditions[0], seed));
    std::ofstream(replicate_dir(dir / "out", spec.conditions[0], seed) / "config.toml") << run;
  }
  CountedTask::made = 0;
  ExperimentOptions restart;
  restart.restart_changed = true;
  write_experiment_plan(spec, dir / "out", restart);
  EXPECT_EQ(CountedTask::made, 0) << "checking the kept runs made the task";
  EXPECT_TRUE(fs::exists(replicate_dir(dir / "out", spec.conditions[0], 1) / "config.toml"));
  EXPECT_FALSE(fs::exists(replicate_dir(dir / "out", spec.conditions[0], 2) / "config.toml"));  // started over
  fs::remove_all(dir);
  unregister_task_plugin("counted");
}

}  // namespace
}  // namespace qdmeta
