#include "qdmeta/plugin/task_registry.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/registry.hpp"

namespace qdmeta {
namespace {

Registry<TaskPlugin>& tasks() {
  static Registry<TaskPlugin> r;
  return r;
}

using MetaObjectives = std::vector<std::pair<std::string, MetaObjectiveReader>>;

MetaObjectives::iterator kind_in(MetaObjectives& kinds, std::string_view kind) {
  return std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == kind; });
}

}  // namespace

void register_task_plugin(const std::string& name, TaskPlugin plugin) { tasks().add(name, std::move(plugin)); }

void register_meta_objective(std::string_view task, const std::string& kind, MetaObjectiveReader reader) {
  const bool registered = tasks().update(task, [&](TaskPlugin& plugin) {
    auto& kinds = plugin.meta_objectives;
    if (const auto entry = kind_in(kinds, kind); entry != kinds.end()) entry->second = std::move(reader);
    else kinds.emplace_back(kind, std::move(reader));
    return true;
  });
  if (!registered)
    throw Error(fmt::format("register_meta_objective: task '{}' is not registered", task));
}

bool unregister_task_plugin(std::string_view name) { return tasks().remove(name); }

bool unregister_meta_objective(std::string_view task, std::string_view kind) {
  return tasks().update(task, [&](TaskPlugin& plugin) {
    auto& kinds = plugin.meta_objectives;
    const auto entry = kind_in(kinds, kind);
    if (entry == kinds.end()) return false;
    kinds.erase(entry);
    return true;
  });
}

void register_unavailable_task(const std::string& name, std::string why) { tasks().add_unavailable(name, std::move(why)); }

std::shared_ptr<const TaskPlugin> find_task_plugin(std::string_view name) { return tasks().find(name); }

std::vector<std::string> registered_task_names() {
  std::vector<std::string> names = tasks().names();
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> unavailable_task_names() { return tasks().unavailable_names(); }

std::vector<std::string> adaptation_test_names(const TaskPlugin& plugin) {
  std::vector<std::string> names = plugin.adaptation_tests;
  if (!plugin.generalisation_groups.empty()) names.emplace_back("generalisation");
  return names;
}

std::string describe_adaptation_tests() {
  std::string out;
  for (const auto& name : registered_task_names()) {
    const auto plugin = find_task_plugin(name);
    if (plugin == nullptr || plugin->adaptation_tests.empty()) continue;
    out += fmt::format("{}{}: {}", out.empty() ? "" : "; ", name, fmt::join(adaptation_test_names(*plugin), ", "));
  }
  return out;
}

Task read_registered_task(ConfigReader& t) {
  const std::vector<std::string> names = registered_task_names();
  if (names.empty()) throw InputError(fmt::format("{}: no task is registered", t.source()));
  // The documented range is the same in every build: the tasks it has and those it lacks.
  std::vector<std::string> documented = names;
  for (auto& n : unavailable_task_names()) documented.push_back(n);
  std::sort(documented.begin(), documented.end());
  const std::string fallback = std::find(names.begin(), names.end(), "rastrigin") != names.end() ? "rastrigin" : names.front();
  const std::string name = t.string("name", fallback, quoted_names(documented));
  if (const auto plugin = find_task_plugin(name))
    return t.resolving() && plugin->read_shape ? task_of_shape(plugin->read_shape(t)) : plugin->read_task(t);
  std::string why = tasks().why_unavailable(name);
  // A name this build never had: most often a run made by a program that handed its task over as
  // a part (RunParts::task) and is now resumed or rebuilt without it.
  if (why.empty())
    why = "no task of that name is registered here: a task handed over as a part (RunParts::task) must be handed "
          "again, e.g. open_for_resume(dir, parts), or registered with register_task_plugin before run_cli";
  t.not_a_valid_choice("name", name, quoted_names(names), fmt::format(" ({})", why));
}

std::unique_ptr<MetaObjective> read_registered_meta_objective(ConfigReader& m, const Task& task, std::uint64_t seed) {
  const auto plugin = find_task_plugin(task.name());
  if (plugin == nullptr || plugin->meta_objectives.empty())
    throw InputError(fmt::format("{}: task '{}' has no meta-fitness yet", m.source(), task.name()));
  std::vector<std::string> kinds;
  for (const auto& [kind, reader] : plugin->meta_objectives) kinds.push_back(kind);
  const std::string fallback = kinds.front();
  std::sort(kinds.begin(), kinds.end());  // listed alphabetically, as docs/config.md does
  const std::string valid = quoted_names(kinds);
  const std::string kind = m.string("kind", fallback, valid);
  for (const auto& [name, reader] : plugin->meta_objectives)
    if (name == kind) return reader(m, task, seed);
  m.not_a_valid_choice("kind", kind, valid);
}

}  // namespace qdmeta
