#pragma once
// Tasks plug into the config reader here, found by the name that `[task] name` selects: the
// built-in Rastrigin (tasks/rastrigin/rastrigin_config.hpp), an optional component (the RHex task
// in DART) or a user's own task, each through the same register_task_plugin(). A plugin says how
// to read its [task] table, its meta-objectives by [meta_fitness] kind, and its test families
// (`qdmeta adapt --test NAME`). Registration is explicit (a main calls e.g. register_rhex_task()
// at start-up), never a static initialiser, which static libraries would drop. The registry is a
// Registry (plugin/registry.hpp) of TaskPlugin values; a task's meta-objective kinds are part of
// its value, edited copy-on-write.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/task_shape.hpp"

namespace qdmeta {

class ConfigReader;

// Reads the rest of a [meta_fitness] table (`kind` is already read) for `task`; `seed` drives
// choices made once per replicate, which the reader writes to the resolved config. While the
// config is only resolved (meta_fitness.resolving()) `task` may be a shape (core/task_shape.hpp): the
// reader reads and checks its keys and returns nullptr, making nothing.
using MetaObjectiveReader =
    std::function<std::unique_ptr<MetaObjective>(ConfigReader& meta_fitness, const Task& task, std::uint64_t seed)>;

struct TaskPlugin {
  // Reads the rest of the [task] table (`name` is already read) and builds the task.
  std::function<Task(ConfigReader& task_table)> read_task;
  // Optional: reads the same keys as read_task, checks them, and returns the task's shape without
  // making the task, for a config that is only resolved (ConfigReader::resolving(): an
  // experiment's conditions, its kept runs). Without it, resolving makes the task.
  std::function<TaskShape(ConfigReader& task_table)> read_shape;
  // The meta-objectives QD-Meta can use on this task, by [meta_fitness] kind; the first is the
  // default kind. register_meta_objective() adds more.
  std::vector<std::pair<std::string, MetaObjectiveReader>> meta_objectives;
  // Optional: the test phase (`qdmeta adapt --test NAME`). Builds family `test` (one of
  // `adaptation_tests`) for a finished run; `config` is the run's resolved config (its seed and
  // [meta_fitness] say what it trained on), `source` names it in messages, `seed` is the adapt seed.
  std::function<std::unique_ptr<AdaptationTests>(const toml::table& config, const std::string& source, const Task& task,
                                                 std::string_view test, std::uint64_t seed)>
      read_adaptation_tests;
  std::vector<std::string> adaptation_tests;  // the family names read_adaptation_tests accepts
  // Families whose whole-archive means make the generalisation test (`qdmeta adapt --test
  // generalisation`), in the order they are reported; empty: the task has none.
  std::vector<std::string> generalisation_groups;
};

// Registers (or replaces) the plugin for `name`. Thread-safe. The built-in plugins are
// registered the same way (assembly/core_plugins.hpp).
void register_task_plugin(const std::string& name, TaskPlugin plugin);
// Adds (or replaces) meta-objective `kind` of the registered task `task`; Error when `task` is
// not registered.
void register_meta_objective(std::string_view task, const std::string& kind, MetaObjectiveReader reader);
// Remove a plugin, or one meta-objective kind of a registered task; false when there was none.
// Lookups already made keep their snapshots. (A part used for one run only needs no
// registration at all: hand it to build_run() as a value, assembly/run_parts.hpp.)
bool unregister_task_plugin(std::string_view name);
bool unregister_meta_objective(std::string_view task, std::string_view kind);
// A task this build lacks but a user may ask for: `[task] name = NAME` then fails with `why`
// ("this build has no RHex task: it needs DART"). A real plugin of that name takes precedence.
void register_unavailable_task(const std::string& name, std::string why);

// The plugin registered under `name`, or nullptr: a snapshot, which later registrations (of this
// name too) leave unchanged.
std::shared_ptr<const TaskPlugin> find_task_plugin(std::string_view name);
// Registered names, sorted.
std::vector<std::string> registered_task_names();
// Names registered as unavailable (register_unavailable_task) and not registered since, sorted.
std::vector<std::string> unavailable_task_names();
// A task's `qdmeta adapt --test` names: its families, then "generalisation" where it has one.
std::vector<std::string> adaptation_test_names(const TaskPlugin& plugin);
// The registered test families of every task, "rastrigin: dimension, translation; rhex: ...",
// with "generalisation" where a task has one (the help text of `qdmeta adapt --test`).
std::string describe_adaptation_tests();

// Reads `[task] name` and builds that task through its plugin; while resolving, only its shape
// (core/task_shape.hpp) where the plugin has read_shape. An unknown name is an InputError listing the
// registered names (and why an unavailable one is missing).
Task read_registered_task(ConfigReader& task_table);
// Reads `[meta_fitness] kind` (default: the task's first) and builds that meta-objective.
std::unique_ptr<MetaObjective> read_registered_meta_objective(ConfigReader& meta_fitness, const Task& task,
                                                              std::uint64_t seed);

}  // namespace qdmeta
