// Tests of build_run() with parts handed over as values (src/qdmeta/assembly/run_parts.hpp):
// a part is used in place of the registry's, the config only names it (a different name is
// refused), the builder protocol still runs around it, and nothing is registered.
#include "plane_task.hpp"
#include "qdmeta/assembly/run_parts.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {
namespace {

using test::Plane;

// A meta-objective with no tasks of its own: the mean first gene of the elites.
class MeanFirstGene final : public MetaObjective {
 public:
  std::string name() const override { return "mean-first-gene"; }
  MetaPlan plan(const MetaArchive&, Rng&) const override { return {}; }
  MetaFitnessResult score(const MetaArchive& archive, const MetaPlan&, std::span<const EvaluationBatch>) const override {
    const RowMatrix& elites = archive.genotypes();
    return {elites.rows() == 0 ? 0.0 : static_cast<double>(elites.col(0).mean()), 0};
  }
};

// The meta-objective part; `reads` counts the runs it was made for.
MetaObjectivePart mean_first_gene(int& reads) {
  return {"mean-first-gene", [&reads](ConfigReader&, const Task&, std::uint64_t) -> std::unique_ptr<MetaObjective> {
            ++reads;
            return std::make_unique<MeanFirstGene>();
          }};
}

std::vector<std::string> meta_objective_kinds(const std::string& task) {
  std::vector<std::string> kinds;
  for (const auto& [kind, reader] : find_task_plugin(task)->meta_objectives) kinds.push_back(kind);
  return kinds;
}

TEST(RunParts, ATaskPartIsUsedAndTheConfigOnlyRecordsItsName) {
  ensure_core_plugins();
  RunParts parts;
  parts.task = Task(Plane{});
  const BuiltRun built = build_run(toml::parse("[budget]\nevaluations = 1000\n"), "x.toml", {}, parts);
  ASSERT_EQ(built.evaluation_tasks.size(), 1u);
  EXPECT_EQ(built.evaluation_tasks.front().id(), parts.task->id());
  EXPECT_EQ(built.settings.task, "plane");
  EXPECT_EQ(built.resolved["task"]["name"].value<std::string>(), "plane");
  ASSERT_NE(built.algorithm, nullptr);
  EXPECT_EQ(find_task_plugin("plane"), nullptr);  // nothing registered
  // The same config, named explicitly, builds the same.
  EXPECT_EQ(build_run(toml::parse("[task]\nname = \"plane\"\n"), "x.toml", {}, parts).settings.task, "plane");
}

TEST(RunParts, AConfigNamingAnotherTaskOrGivingTaskKeysIsRefused) {
  RunParts parts;
  parts.task = Task(Plane{});
  EXPECT_INPUT_ERROR(build_run(toml::parse("[task]\nname = \"rastrigin\"\n"), "x.toml", {}, parts),
                     "x.toml: task.name = \"rastrigin\" is not a valid choice: use one of \"plane\" (the part handed "
                     "over)");
  // The part is the task: a key of the registered task's table configures nothing, so it is refused.
  EXPECT_INPUT_ERROR(build_run(toml::parse("[task]\ndimensions = 4\n"), "x.toml", {}, parts),
                     "x.toml: unknown key 'task.dimensions' in [task] (valid keys: name)");
}

// A run made with a part, resumed (or rebuilt) without it: the message says how to pass it.
TEST(RunParts, ATaskNameNothingRegisteredNamesHowToHandThePartAgain) {
  ensure_core_plugins();
  EXPECT_INPUT_ERROR(build_run(toml::parse("[task]\nname = \"plane\"\n"), "run/config.toml"),
                     "run/config.toml: task.name = \"plane\" is not a valid choice: use one of \"rastrigin\" (no task "
                     "of that name is registered here: a task handed over as a part (RunParts::task) must be handed "
                     "again, e.g. open_for_resume(dir, parts), or registered with register_task_plugin before run_cli)");
}

// Parts are values, not registrations: builds from different parts of one name, at once, each
// get their own (a registry swapped for the length of a build would mix them up).
TEST(RunParts, ThreadsBuildFromDifferentPartsOfOneNameAtOnce) {
  ensure_core_plugins();
  std::atomic<int> mixed_up{0};
  const auto build_many = [&mixed_up](Index genes) {
    RunParts parts;
    parts.task = Task(Plane{genes});
    for (int i = 0; i < 200; ++i)
      if (build_run(toml::table{}, "x.toml", {}, parts, BuildScope::kTasksOnly).evaluation_tasks.front().genotype_size() !=
          genes)
        ++mixed_up;
  };
  std::thread three(build_many, 3);
  std::thread five(build_many, 5);
  three.join();
  five.join();
  EXPECT_EQ(mixed_up.load(), 0);
}

TEST(RunParts, AMetaObjectivePartIsMadeForTheRunAndRegistersNoKind) {
  ensure_core_plugins();
  const std::vector<std::string> kinds_before = meta_objective_kinds("rastrigin");
  int reads = 0;
  RunParts parts;
  parts.meta_objective = mean_first_gene(reads);
  const toml::table config = toml::parse("algorithm = \"qd-meta\"\n[task]\nname = \"rastrigin\"\ndimensions = 4\n");
  const BuiltRun built = build_run(config, "x.toml", {}, parts, BuildScope::kTasksOnly);
  EXPECT_EQ(reads, 1);
  EXPECT_EQ(built.resolved["meta_fitness"]["kind"].value<std::string>(), "mean-first-gene");
  EXPECT_EQ(built.evaluation_tasks.size(), 1u);  // the objective has no tasks of its own
  EXPECT_EQ(meta_objective_kinds("rastrigin"), kinds_before);
  // Without the part, the config's kind is read from the registry again.
  EXPECT_INPUT_ERROR(
      build_run(toml::parse("algorithm = \"qd-meta\"\n[meta_fitness]\nkind = \"mean-first-gene\"\n"), "x.toml", {},
                BuildScope::kTasksOnly),
      "x.toml: meta_fitness.kind = \"mean-first-gene\" is not a valid choice: use one of \"dimension\", "
      "\"translation\"");
  EXPECT_INPUT_ERROR(
      build_run(toml::parse("algorithm = \"qd-meta\"\n[meta_fitness]\nkind = \"dimension\"\n"), "x.toml", {}, parts,
                BuildScope::kTasksOnly),
      "x.toml: meta_fitness.kind = \"dimension\" is not a valid choice: use one of \"mean-first-gene\" (the part "
      "handed over)");
}

TEST(RunParts, AnAlgorithmPartGoesThroughTheBuilderProtocol) {
  ensure_core_plugins();
  const auto map_elites = find_algorithm("map-elites");
  int makes = 0;
  RunParts parts;
  parts.algorithm = AlgorithmPart{"mine", [map_elites, &makes](AlgorithmBuild& b) -> AlgorithmMaker {
                                    AlgorithmMaker inner = (*map_elites)(b);
                                    return [inner = std::move(inner), &makes]() mutable {
                                      ++makes;
                                      return inner();
                                    };
                                  }};
  const BuiltRun built = build_run(toml::parse("[budget]\nevaluations = 100\n"), "x.toml", {}, parts);
  EXPECT_EQ(makes, 1);
  ASSERT_NE(built.algorithm, nullptr);
  EXPECT_EQ(built.settings.algorithm, "mine");
  EXPECT_EQ(built.resolved["algorithm"].value<std::string>(), "mine");
  const auto names = registered_algorithm_names();
  EXPECT_EQ(std::count(names.begin(), names.end(), "mine"), 0);
  // The protocol around it: a misspelt key of the builder's table is refused before anything is made.
  EXPECT_INPUT_ERROR(build_run(toml::parse("[map_elites]\nbatch_sise = 3\n"), "x.toml", {}, parts),
                     "x.toml: unknown key 'map_elites.batch_sise' in [map_elites] (valid keys: "
                     "batch_size, initial_population)");
  EXPECT_EQ(makes, 1);
  EXPECT_INPUT_ERROR(build_run(toml::parse("algorithm = \"map-elites\"\n"), "x.toml", {}, parts),
                     "x.toml: algorithm = \"map-elites\" is not a valid choice: use one of \"mine\" (the part handed "
                     "over)");
}

}  // namespace
}  // namespace qdmeta
