#include "qdmeta/experiment/task_registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <stdexcept>

#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/core_plugins.hpp"

namespace qdmeta {
namespace {

struct Registry {
  std::mutex mutex;
  // Immutable snapshots: a caller's found plugin stays valid and unchanged while others are
  // registered or this one is replaced (register_meta_objective copies, then swaps).
  std::map<std::string, std::shared_ptr<const TaskPlugin>, std::less<>> plugins;
  std::map<std::string, std::string, std::less<>> unavailable;
};

Registry& registry() {
  static Registry r;
  return r;
}

std::string quoted(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", n);
  return out;
}

// Copy-on-write edit of a registered plugin's meta-objectives (holders of the old snapshot keep
// it): `edit(kinds, entry)` gets the list and the entry of `kind` (or kinds.end()) and returns
// whether it changed anything; only then is the copy swapped in. Call with the registry locked.
template <class Edit>
bool edit_meta_objectives(std::shared_ptr<const TaskPlugin>& plugin, std::string_view kind, Edit&& edit) {
  auto updated = std::make_shared<TaskPlugin>(*plugin);
  auto& kinds = updated->meta_objectives;
  const auto entry = std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == kind; });
  if (!edit(kinds, entry)) return false;
  plugin = std::move(updated);
  return true;
}

}  // namespace

void register_task_plugin(const std::string& name, TaskPlugin plugin) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.plugins[name] = std::make_shared<const TaskPlugin>(std::move(plugin));
}

void register_meta_objective(std::string_view task, const std::string& kind, MetaObjectiveReader reader) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.plugins.find(task);
  if (it == r.plugins.end())
    throw std::logic_error(fmt::format("register_meta_objective: task '{}' is not registered", task));
  edit_meta_objectives(it->second, kind, [&](auto& kinds, auto entry) {
    if (entry != kinds.end()) entry->second = std::move(reader);
    else kinds.emplace_back(kind, std::move(reader));
    return true;
  });
}

bool unregister_task_plugin(std::string_view name) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.plugins.find(name);
  if (it == r.plugins.end()) return false;
  r.plugins.erase(it);
  return true;
}

bool unregister_meta_objective(std::string_view task, std::string_view kind) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.plugins.find(task);
  if (it == r.plugins.end()) return false;
  return edit_meta_objectives(it->second, kind, [](auto& kinds, auto entry) {
    if (entry == kinds.end()) return false;
    kinds.erase(entry);
    return true;
  });
}

void register_unavailable_task(const std::string& name, std::string why) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  r.unavailable[name] = std::move(why);
}

std::shared_ptr<const TaskPlugin> find_task_plugin(std::string_view name) {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto it = r.plugins.find(name);
  return it == r.plugins.end() ? nullptr : it->second;
}

std::vector<std::string> registered_task_names() {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, plugin] : r.plugins) names.push_back(name);
  return names;
}

std::string describe_adaptation_tests() {
  std::string out;
  for (const auto& name : registered_task_names()) {
    const auto plugin = find_task_plugin(name);
    if (plugin == nullptr || plugin->adaptation_tests.empty()) continue;
    std::string families;
    for (const auto& t : plugin->adaptation_tests) families += fmt::format("{}{}", families.empty() ? "" : ", ", t);
    if (!plugin->generalisation_groups.empty()) families += ", generalisation";
    out += fmt::format("{}{}: {}", out.empty() ? "" : "; ", name, families);
  }
  return out;
}

std::vector<std::string> unavailable_task_names() {
  ensure_core_plugins();
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, why] : r.unavailable)
    if (!r.plugins.contains(name)) names.push_back(name);
  return names;
}

Task read_registered_task(ConfigReader& t) {
  const std::vector<std::string> names = registered_task_names();
  const std::string valid = quoted(names);
  // The documented range is the same in every build: the tasks it has and those it lacks.
  std::vector<std::string> documented = names;
  for (auto& n : unavailable_task_names()) documented.push_back(n);
  std::sort(documented.begin(), documented.end());
  const std::string fallback = std::find(names.begin(), names.end(), "rastrigin") != names.end() ? "rastrigin" : names.front();
  const std::string name = t.string("name", fallback, quoted(documented));
  if (const auto plugin = find_task_plugin(name)) return plugin->read_task(t);
  std::string why;
  {
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    if (const auto it = r.unavailable.find(name); it != r.unavailable.end()) why = fmt::format(" ({})", it->second);
  }
  throw InputError(
      fmt::format("{}: task.name = \"{}\" is not a valid choice: use one of {}{}", t.source(), name, valid, why));
}

std::unique_ptr<MetaObjective> read_registered_meta_objective(ConfigReader& m, const Task& task, std::uint64_t seed) {
  const auto plugin = find_task_plugin(task.name());
  if (plugin == nullptr || plugin->meta_objectives.empty())
    throw InputError(fmt::format("{}: task '{}' has no meta-fitness yet", m.source(), task.name()));
  std::vector<std::string> kinds;
  for (const auto& [kind, reader] : plugin->meta_objectives) kinds.push_back(kind);
  const std::string fallback = kinds.front();
  std::sort(kinds.begin(), kinds.end());  // listed alphabetically, as docs/config.md does
  const std::string valid = quoted(kinds);
  const std::string kind = m.string("kind", fallback, valid);
  for (const auto& [name, reader] : plugin->meta_objectives)
    if (name == kind) return reader(m, task, seed);
  throw InputError(
      fmt::format("{}: meta_fitness.kind = \"{}\" is not a valid choice: use one of {}", m.source(), kind, valid));
}

}  // namespace qdmeta
