#include "qdmeta/assembly/core_plugins.hpp"

#include <mutex>

#include "qdmeta/assembly/builtin_algorithms.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/part_registries.hpp"
#include "qdmeta/plugin/task_registry.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_config.hpp"

namespace qdmeta {
namespace {

void register_core_plugins() {
  register_unavailable_task("rhex", "this build has no RHex task: it needs DART");
  if (find_task_plugin("rastrigin") == nullptr) register_rastrigin_task();
  for (auto& [name, builder] : builtin_algorithms())
    if (find_algorithm(name) == nullptr) register_algorithm(name, std::move(builder));
  if (!controller_registry().contains("static")) controller_registry().add("static", read_static_control);
  if (!controller_registry().contains("sarsa")) controller_registry().add("sarsa", read_sarsa_control);
}

}  // namespace

void ensure_core_plugins() {
  static std::once_flag once;
  std::call_once(once, register_core_plugins);
}

}  // namespace qdmeta
