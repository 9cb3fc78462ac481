// Tests of the parts handed to build_run() beside a task, meta-objective, algorithm and variation
// (src/qdmeta/assembly/run_parts.hpp): a task that reads its own [task] keys, a controller, a
// feature-map and an archive. Each is used without registering anything, reads its own keys from
// the one config (a misspelt one is refused), gives what the same part gives when registered,
// and a part the run's algorithm does not read is refused rather than ignored.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "plane_task.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/part_registries.hpp"
#include "qdmeta/run/run_directory.hpp"

namespace qdmeta {
namespace {

using test::Plane;

TaskPart plane_reading_its_keys() {
  return {"plane", [](ConfigReader& t) { return Task(Plane{t.integer("genes", 3, 1, 100)}); }};
}

TEST(TaskPart, ReadsItsOwnKeysFromTheRunsTaskTable) {
  ensure_core_plugins();
  RunParts parts;
  parts.task_reader = plane_reading_its_keys();
  const BuiltRun built = build_run(toml::parse("[task]\nname = \"plane\"\ngenes = 5\n"), "x.toml", {}, parts);
  EXPECT_EQ(built.evaluation_tasks.front().genotype_size(), 5);
  EXPECT_EQ(built.resolved["task"]["genes"].value<std::int64_t>(), 5);
  EXPECT_EQ(build_run(toml::table{}, "x.toml", {}, parts).resolved["task"]["name"].value<std::string>(), "plane");
  EXPECT_INPUT_ERROR(build_run(toml::parse("[task]\ngenez = 5\n"), "x.toml", {}, parts),
                     "x.toml: unknown key 'task.genez' in [task] (valid keys: genes, name)");
  EXPECT_INPUT_ERROR(build_run(toml::parse("[task]\ngenes = 0\n"), "x.toml", {}, parts),
                     "x.toml: task.genes = 0 is out of range: must be in [1, 100]");
  parts.task = Task(Plane{});
  EXPECT_INPUT_ERROR(build_run(toml::table{}, "x.toml", {}, parts),
                     "x.toml: RunParts holds a task and a task_reader: give one of them");
  RunParts misnamed;
  misnamed.task_reader = TaskPart{"flat", [](ConfigReader&) { return Task(Plane{}); }};
  EXPECT_INPUT_ERROR(build_run(toml::table{}, "x.toml", {}, misnamed),
                     "x.toml: the task part \"flat\" made a task named 'plane': they must be the same name");
}

// QD-Meta on a small Rastrigin, with `extra` TOML appended.
std::string qd_meta_config(const std::string& extra) {
  return "algorithm = \"qd-meta\"\n[task]\ndimensions = 4\n[archive]\nbins = [5, 5]\n[qd_meta]\nmeta_population = 2\n"
         "batch_size = 10\ninitial_population = 20\ndatabase_capacity = 1000\n" +
         extra;
}

// G = 1, 2, 3, 1, 2, 3, ... from `first`, recorded.
class Cycle final : public GenerationController {
 public:
  Cycle(int first, std::vector<int>* chosen) : next_(first), chosen_(chosen) {}
  std::string name() const override { return "cycle"; }
  int choose_generations(const Eigen::MatrixXd&, Rng&) override {
    const int g = next_;
    next_ = next_ % 3 + 1;
    chosen_->push_back(g);
    return g;
  }
  int max_generations() const override { return 3; }
  void observe(std::span<const double>, std::int64_t) override {}
  void save(BinaryWriter&) const override {}
  void load(BinaryReader&) override {}

 private:
  int next_;
  std::vector<int>* chosen_;
};

TEST(ControllerPart, ChoosesQdMetasGenerationsWithoutARegistration) {
  ensure_core_plugins();
  std::vector<int> chosen;
  RunParts parts;
  parts.controller = ControllerPart{"cycle", [&chosen](ConfigReader& c) -> std::unique_ptr<GenerationController> {
                                      return std::make_unique<Cycle>(static_cast<int>(c.integer("first", 1, 1, 3)),
                                                                     &chosen);
                                    }};
  const BuiltRun built = build_run(toml::parse(qd_meta_config("[control]\nfirst = 2\n")), "x.toml", {}, parts);
  EXPECT_EQ(built.resolved["control"]["kind"].value<std::string>(), "cycle");
  SerialEvaluator evaluator;
  for (int t = 0; t < 4; ++t) built.algorithm->step(evaluator);
  EXPECT_EQ(chosen, (std::vector<int>{2, 3, 1, 2}));
  EXPECT_FALSE(controller_registry().contains("cycle"));
  EXPECT_INPUT_ERROR(build_run(toml::parse(qd_meta_config("[control]\nkind = \"sarsa\"\n")), "x.toml", {}, parts),
                     "x.toml: control.kind = \"sarsa\" is not a valid choice: use one of \"cycle\" (the part handed "
                     "over)");
  const std::string misspelt = input_error_message(
      [&] { build_run(toml::parse(qd_meta_config("[control]\nfirts = 2\n")), "x.toml", {}, parts); });
  EXPECT_TRUE(misspelt.starts_with("x.toml: unknown key 'control.firts' in [control]")) << misspelt;
  // MAP-Elites has no controller: the part is refused, not ignored.
  EXPECT_INPUT_ERROR(build_run(toml::table{}, "x.toml", {}, parts),
                     "x.toml: the controller part \"cycle\" was handed over, but algorithm 'map-elites' does not read "
                     "[control] kind \"cycle\": leave the part out, or choose an algorithm that takes it");
}

// Rastrigin MAP-Elites on a 12 x 12 grid, with `extra` TOML appended.
toml::table map_elites_config(const std::string& extra) {
  return toml::parse(
      "algorithm = \"map-elites\"\nseed = 7\n[task]\nname = \"rastrigin\"\ndimensions = 6\n"
      "[map_elites]\nbatch_size = 50\ninitial_population = 100\n" +
      extra);
}

EliteTable run_generations(Algorithm& algorithm, int generations) {
  SerialEvaluator evaluator;
  for (int g = 0; g < generations; ++g) algorithm.step(evaluator);
  return algorithm.elites();
}

// Target feature k: base feature `order[k]` (a permutation of "select"'s choice).
class Pick final : public FeatureMap {
 public:
  Pick(Index inputs, std::vector<Index> order) : inputs_(inputs), order_(std::move(order)) {}
  Index input_size() const override { return inputs_; }
  Index output_size() const override { return static_cast<Index>(order_.size()); }
  void map(const Real* base, Index count, Real* target) const override {
    for (Index r = 0; r < count; ++r)
      for (std::size_t k = 0; k < order_.size(); ++k) target[r * output_size() + k] = base[r * inputs_ + order_[k]];
  }

 private:
  Index inputs_;
  std::vector<Index> order_;
};

TEST(FeatureMapPart, GivesMapElitesTheMeasuresOfTheSameSelectionByKey) {
  ensure_core_plugins();
  RunParts parts;
  parts.feature_map = FeatureMapPart{"pick", [](ConfigReader& f, Index base, Index targets) -> std::unique_ptr<FeatureMap> {
                                       const Index first = f.integer("first", 0, 0, base - 1);
                                       if (targets != 2) throw InputError("pick makes 2 target features");
                                       return std::make_unique<Pick>(base, std::vector<Index>{first, 1 - first});
                                     }};
  // Base features 1 then 0, by the part and by "select" with archive.measures: the same run.
  const BuiltRun by_part =
      build_run(map_elites_config("[archive]\nbins = [12, 12]\n[feature_map]\nfirst = 1\n"), "x.toml", {}, parts);
  const BuiltRun by_select = build_run(map_elites_config("[archive]\nbins = [12, 12]\nmeasures = [1, 0]\n"), "x.toml");
  EXPECT_EQ(by_part.resolved["feature_map"]["kind"].value<std::string>(), "pick");
  const EliteTable a = run_generations(*by_part.algorithm, 6);
  const EliteTable b = run_generations(*by_select.algorithm, 6);
  ASSERT_GT(a.size(), 10);
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.solutions, b.solutions);
  EXPECT_EQ(a.measures, b.measures);
  EXPECT_FALSE(feature_map_registry().contains("pick"));
  EXPECT_INPUT_ERROR(build_run(map_elites_config("[archive]\nbins = [4, 4, 4]\n"), "x.toml", {}, parts),
                     "x.toml: pick makes 2 target features");
  EXPECT_INPUT_ERROR(
      build_run(toml::parse(qd_meta_config("")), "x.toml", {}, parts),
      "x.toml: the feature-map part \"pick\" was handed over, but algorithm 'qd-meta' does not read [feature_map] "
      "kind \"pick\": leave the part out, or choose an algorithm that takes it");
  parts.feature_map->kind = "select";
  EXPECT_INPUT_ERROR(build_run(map_elites_config(""), "x.toml", {}, parts),
                     "x.toml: the feature-map part handed over is named \"select\", a built-in kind: give it another "
                     "name");
}

TEST(ArchivePart, RunsMapElitesWithTheGridsBits) {
  ensure_core_plugins();
  RunParts parts;
  parts.archive = ArchivePart{"wrapped-grid", [](ConfigReader& a, const ArchiveShape& shape, MemoryEstimate& memory) {
                                GridArchiveParams p;
                                const auto side = static_cast<int>(a.integer("side", 10, 1, 1000));
                                p.bins = {side, side};
                                p.solution_size = shape.solution_size;
                                p.qd_offset = shape.qd_offset;
                                memory.add("the test's archive", "side^2 x genes", grid_archive_bytes(p));
                                return AnyArchive(GridArchive(p));
                              }};
  const BuiltRun wrapped = build_run(map_elites_config("[archive]\nside = 12\n"), "x.toml", {}, parts);
  ASSERT_NE(dynamic_cast<BasicMapElites<AnyArchive>*>(wrapped.algorithm.get()), nullptr);
  EXPECT_EQ(wrapped.resolved["archive"]["kind"].value<std::string>(), "wrapped-grid");
  const BuiltRun grid = build_run(map_elites_config("[archive]\nbins = [12, 12]\n"), "x.toml");
  const EliteTable a = run_generations(*wrapped.algorithm, 8);
  const EliteTable b = run_generations(*grid.algorithm, 8);
  ASSERT_GT(a.size(), 10);
  EXPECT_EQ(a.index, b.index);
  EXPECT_EQ(a.objective, b.objective);
  EXPECT_EQ(a.solutions, b.solutions);
  EXPECT_FALSE(archive_registry().contains("wrapped-grid"));
  const std::string misspelt = input_error_message(
      [&] { build_run(map_elites_config("[archive]\nbins = [12, 12]\n"), "x.toml", {}, parts); });
  EXPECT_TRUE(misspelt.starts_with("x.toml: unknown key 'archive.bins' in [archive]")) << misspelt;
  EXPECT_INPUT_ERROR(build_run(toml::parse(qd_meta_config("")), "x.toml", {}, parts),
                     "x.toml: the archive part \"wrapped-grid\" was handed over, but algorithm 'qd-meta' does not "
                     "read [archive] kind \"wrapped-grid\": leave the part out, or choose an algorithm that takes it");
  parts.archive->kind = "grid";
  EXPECT_INPUT_ERROR(build_run(map_elites_config(""), "x.toml", {}, parts),
                     "x.toml: the archive part handed over is named \"grid\", a built-in kind: give it another name");
}

// A run made with a part, resumed without it: the registry's "not a valid choice" says how to hand
// it again. Refused before its checkpoint is read, so a config.toml is all the directory needs.
TEST(PartsOnResume, APartNotHandedAgainIsNamedWithHowToPassIt) {
  ensure_core_plugins();
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("qdmeta-parts-on-resume-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "config.toml") << qd_meta_config("[control]\nkind = \"cycle\"\n");
  const std::string config = (dir / "config.toml").string();
  // The registered kinds listed between depend on what this process registered before.
  const std::string message = input_error_message([&] { open_for_resume(dir, {}); });
  EXPECT_TRUE(message.starts_with(config + ": control.kind = \"cycle\" is not a valid choice: use one of \"static\", "
                                           "\"sarsa\""))
      << message;
  EXPECT_TRUE(message.ends_with("; a part that the run in " + dir.string() + " was made with, handed to build_run() as "
                                "a value, is neither registered here nor handed over again: resume with the same parts, "
                                "open_for_resume(dir, parts) (RunParts, qdmeta/assembly/run_parts.hpp), or register it"))
      << message;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace qdmeta
