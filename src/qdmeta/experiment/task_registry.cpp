#include "qdmeta/experiment/task_registry.hpp"

#include <map>
#include <mutex>

namespace qdmeta {
namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, std::unique_ptr<TaskPlugin>, std::less<>> plugins;
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

void register_task_plugin(const std::string& name, TaskPlugin plugin) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.plugins[name] = std::make_unique<TaskPlugin>(std::move(plugin));
}

const TaskPlugin* find_task_plugin(std::string_view name) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.plugins.find(name);
  return it == r.plugins.end() ? nullptr : it->second.get();
}

std::vector<std::string> registered_task_names() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, plugin] : r.plugins) names.push_back(name);
  return names;
}

}  // namespace qdmeta
