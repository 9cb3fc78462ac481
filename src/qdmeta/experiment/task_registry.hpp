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
};

// Registers (or replaces) the plugin for `name`. Thread-safe.
void register_task_plugin(const std::string& name, TaskPlugin plugin);
// The plugin registered under `name`, or nullptr.
const TaskPlugin* find_task_plugin(std::string_view name);
// Registered names, sorted.
std::vector<std::string> registered_task_names();

}  // namespace qdmeta
