// The readers that turn a config's names into registered plugins (src/qdmeta/plugin): a part's
// `kind` (read_kind), the [task] name, the [meta_fitness] kind, and the algorithm registry they
// sit beside. A name absent takes the documented default, recorded in the resolved config; an
// unknown name is one line that lists the valid ones; a registered part may not take a built-in
// kind's name. Registering a name again replaces the plugin in its place (the registries'
// documented rule), while a found plugin stays the one found. The expected lists are taken from
// the registries, so plugins other tests of this binary register do not matter.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "expect_input_error.hpp"
#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/part_registries.hpp"
#include "qdmeta/plugin/registry.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {
namespace {

using Names = std::vector<std::string>;

struct OneGeneTask {
  int genes = 1;
  std::string name() const { return "readers-test-task"; }
  Index genotype_size() const { return genes; }
  Index base_feature_size() const { return 0; }
  void evaluate(GenotypeView, EvaluationView) const {}
};

// `kind` of [mutation] in `text`, read with read_kind; what the resolved config recorded goes to
// `recorded`.
std::string kind_of(const std::string& text, const Names& builtin, const Names& registered,
                    std::string* recorded = nullptr) {
  const toml::table config = toml::parse(text);
  toml::table resolved;
  ConfigReader root(config, "cfg.toml", resolved);
  ConfigReader mutation = root.table("mutation");
  const std::string kind = read_kind(mutation, builtin, registered, "gaussian");
  if (recorded) *recorded = resolved["mutation"]["kind"].value_or<std::string>("(none)");
  return kind;
}

TEST(ReadKind, AnAbsentKindIsTheDefaultAndIsRecorded) {
  std::string recorded;
  EXPECT_EQ(kind_of("[mutation]\nrate = 0.1\n", {"gaussian", "iso-line"}, {"mine"}, &recorded), "gaussian");
  EXPECT_EQ(recorded, "gaussian");
  EXPECT_EQ(kind_of("[mutation]\nkind = \"mine\"\n", {"gaussian", "iso-line"}, {"mine"}, &recorded), "mine");
  EXPECT_EQ(recorded, "mine");
}

TEST(ReadKind, AnUnknownKindListsTheBuiltInAndRegisteredOnes) {
  EXPECT_INPUT_ERROR((void)kind_of("[mutation]\nkind = \"gausian\"\n", {"gaussian", "iso-line"}, {"mine", "theirs"}),
                     "cfg.toml: mutation.kind = \"gausian\" is not a valid choice: use one of \"gaussian\", "
                     "\"iso-line\", \"mine\", \"theirs\"");
}

TEST(ReadKind, ARegisteredPartMayNotTakeABuiltInKindsName) {
  // Refused whichever kind the table names: the clash is the program's, not the config's.
  for (const char* text : {"[mutation]\nkind = \"gaussian\"\n", "[mutation]\n"})
    EXPECT_INPUT_ERROR((void)kind_of(text, {"gaussian", "iso-line"}, {"mine", "iso-line"}),
                       "cfg.toml: this program registered a part under \"iso-line\", a built-in kind of this table: "
                       "register it under another name");
}

Task read_task_table(const std::string& text, toml::table& resolved) {
  const toml::table config = toml::parse(text);
  ConfigReader root(config, "cfg.toml", resolved);
  ConfigReader task = root.table("task");
  return read_registered_task(task);
}

TEST(ReadRegisteredTask, ANamedTaskIsBuiltByItsReaderWithItsOwnKeys) {
  TaskPlugin plugin;
  plugin.read_task = [](ConfigReader& t) {
    return Task(OneGeneTask{static_cast<int>(t.integer("genes", 1, 1, 10))});
  };
  register_task_plugin("readers-test-task", plugin);
  toml::table resolved;
  const Task task = read_task_table("[task]\nname = \"readers-test-task\"\ngenes = 3\n", resolved);
  EXPECT_EQ(task.name(), "readers-test-task");
  EXPECT_EQ(task.genotype_size(), 3);
  EXPECT_EQ(resolved["task"]["name"].value<std::string>(), "readers-test-task");
  EXPECT_EQ(resolved["task"]["genes"].value<std::int64_t>(), 3);
  EXPECT_TRUE(unregister_task_plugin("readers-test-task"));
}

TEST(ReadRegisteredTask, AnUnknownNameListsTheRegisteredTasksAndSaysWhy) {
  TaskPlugin plugin;
  plugin.read_task = [](ConfigReader&) { return Task(OneGeneTask{}); };
  register_task_plugin("readers-test-task", plugin);
  register_unavailable_task("readers-test-missing", "not in this build: it needs a library this build lacks");
  const std::string registered = quoted_names(registered_task_names());
  toml::table resolved;
  EXPECT_INPUT_ERROR((void)read_task_table("[task]\nname = \"readers-test-missing\"\n", resolved),
                     "cfg.toml: task.name = \"readers-test-missing\" is not a valid choice: use one of " + registered +
                         " (not in this build: it needs a library this build lacks)");
  const std::string message = input_error_message([&] { (void)read_task_table("[task]\nname = \"nosuch\"\n", resolved); });
  EXPECT_TRUE(message.starts_with("cfg.toml: task.name = \"nosuch\" is not a valid choice: use one of " + registered +
                                  " (no task of that name is registered here: "))
      << message;
  EXPECT_TRUE(unregister_task_plugin("readers-test-task"));
}

TEST(ReadRegisteredMetaObjective, TheFirstKindIsTheDefaultAndAnUnknownOneListsThemAll) {
  std::string chosen;
  const auto reader = [&chosen](std::string kind) -> MetaObjectiveReader {
    return [&chosen, kind](ConfigReader&, const Task&, std::uint64_t) -> std::unique_ptr<MetaObjective> {
      chosen = kind;
      return nullptr;
    };
  };
  TaskPlugin plugin;
  plugin.read_task = [](ConfigReader&) { return Task(OneGeneTask{}); };
  plugin.meta_objectives = {{"zeta", reader("zeta")}, {"alpha", reader("alpha")}};
  register_task_plugin("readers-test-task", plugin);
  const Task task{OneGeneTask{}};
  const auto read = [&](const std::string& text) {
    const toml::table config = toml::parse(text);
    toml::table resolved;
    ConfigReader root(config, "cfg.toml", resolved);
    ConfigReader m = root.table("meta_fitness");
    (void)read_registered_meta_objective(m, task, 1);
    return resolved["meta_fitness"]["kind"].value_or<std::string>("(none)");
  };
  EXPECT_EQ(read("[meta_fitness]\n"), "zeta");  // the first registered, not the first in the alphabet
  EXPECT_EQ(chosen, "zeta");
  EXPECT_EQ(read("[meta_fitness]\nkind = \"alpha\"\n"), "alpha");
  EXPECT_EQ(chosen, "alpha");
  EXPECT_INPUT_ERROR((void)read("[meta_fitness]\nkind = \"beta\"\n"),
                     "cfg.toml: meta_fitness.kind = \"beta\" is not a valid choice: use one of \"alpha\", \"zeta\"");
  plugin.meta_objectives.clear();
  register_task_plugin("readers-test-task", plugin);
  EXPECT_INPUT_ERROR((void)read("[meta_fitness]\n"), "cfg.toml: task 'readers-test-task' has no meta-fitness yet");
  EXPECT_TRUE(unregister_task_plugin("readers-test-task"));
}

// A builder that makes nothing; `tag` tells builders apart.
AlgorithmBuilder builder_tagged(int tag, int* called) {
  return [tag, called](AlgorithmBuild&) -> AlgorithmMaker {
    *called = tag;
    return {};
  };
}

TEST(AlgorithmRegistry, KeepsRegistrationOrderAndReplacesANameInItsPlace) {
  int called = 0;
  register_algorithm("readers-test-b", builder_tagged(1, &called));
  register_algorithm("readers-test-a", builder_tagged(2, &called));
  const auto held = find_algorithm("readers-test-b");
  ASSERT_NE(held, nullptr);
  register_algorithm("readers-test-b", builder_tagged(3, &called));  // replaced, not added again
  const Names names = registered_algorithm_names();
  const auto b = std::find(names.begin(), names.end(), "readers-test-b");
  const auto a = std::find(names.begin(), names.end(), "readers-test-a");
  ASSERT_NE(b, names.end());
  ASSERT_NE(a, names.end());
  EXPECT_LT(b, a);  // its first place
  EXPECT_EQ(std::count(names.begin(), names.end(), "readers-test-b"), 1);
  toml::table empty, resolved;
  ConfigReader root(empty, "cfg.toml", resolved);
  RunSettings settings;
  BuiltRun built;
  const RunParts parts;
  AlgorithmBuild build{root, Task(OneGeneTask{}), MutationParams{}, settings, built, parts};
  (*held)(build);
  EXPECT_EQ(called, 1);  // the snapshot found before the replacement
  (*find_algorithm("readers-test-b"))(build);
  EXPECT_EQ(called, 3);
  EXPECT_EQ(find_algorithm("readers-test-nosuch"), nullptr);
}

}  // namespace
}  // namespace qdmeta
