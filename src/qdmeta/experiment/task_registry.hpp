#pragma once
// Tasks beyond the built-in Rastrigin plug into the config reader here: an optional component
// (the RHex task in DART) or a user's own task registers how to read its [task] table and its
// [meta_fitness] table under the name that `[task] name` selects. Registration is explicit (the
// CLI calls e.g. register_rhex_task() at start-up), never a static initialiser, so it works from
// static libraries.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

class ConfigReader;

struct TaskPlugin {
  // Reads the rest of the [task] table (`name` is already read) and builds the task.
  std::function<Task(ConfigReader& task_table)> read_task;
  // Reads [meta_fitness] for this task; `seed` drives choices made once per replicate.
  std::function<std::unique_ptr<MetaObjective>(ConfigReader& meta_fitness, const Task& task, std::uint64_t seed)>
      read_meta_fitness;
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

// Registers (or replaces) the plugin for `name`. Thread-safe.
void register_task_plugin(const std::string& name, TaskPlugin plugin);
// The plugin registered under `name`, or nullptr.
const TaskPlugin* find_task_plugin(std::string_view name);
// Registered names, sorted.
std::vector<std::string> registered_task_names();

}  // namespace qdmeta
