#include "python_build.hpp"

#include <fmt/format.h>

#include <sstream>

#include "configured_task.hpp"
#include "python_task.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "toml_convert.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// Sets table[key] to `value`, refusing a different value already there.
void require_key(toml::table& table, const std::string& where, const std::string& key, const std::string& value) {
  if (const auto* existing = table[key].as_string(); existing && existing->get() != value)
    throw py::value_error(fmt::format("config: {}.{} is \"{}\", but the {} given is \"{}\"", where, key,
                                      existing->get(), where == "task" ? "task" : "meta-objective", value));
  table.insert_or_assign(key, value);
}

toml::table& subtable(toml::table& config, const std::string& name) {
  if (!config.contains(name)) config.insert(name, toml::table{});
  auto* t = config[name].as_table();
  if (t == nullptr) throw py::type_error(fmt::format("config: '{}' must be a dict (a TOML table)", name));
  return *t;
}

// A built-in task given as task= is the [task] table it was made from: the config's own [task]
// keys must agree with it, and its keys fill in the rest (else the config's defaults would
// silently replace the task's settings).
void take_builtin_table(toml::table& task, const toml::table& builtin) {
  const auto text = [](const toml::node& n) {
    std::ostringstream s;
    n.visit([&](const auto& v) { s << v; });
    return s.str();
  };
  for (const auto& [key, value] : task)
    if (const toml::node* own = builtin.get(key); own && text(*own) != text(value))
      throw InputError(fmt::format("config: task.{} is {}, but the task given has {}", key.str(), text(value),
                                   text(*own)));
  for (const auto& [key, value] : builtin) task.insert_or_assign(key, value);
}

std::string task_name_of(const toml::table& config) {
  if (const auto* t = config["task"].as_table())
    if (const auto* n = (*t)["name"].as_string()) return n->get();
  return "rastrigin";  // the config's default task
}

MetaObjectiveReader reader_of(const TaskPlugin& plugin, const std::string& kind) {
  for (const auto& [name, reader] : plugin.meta_objectives)
    if (name == kind) return reader;
  return {};
}

}  // namespace

// The built-in plugins are registered once, when the module is imported.
ScopedParts::ScopedParts(const PythonParts& parts, const std::string& task_name) {
  if (parts.task && is_python_task(*parts.task)) {
    const Task task = *parts.task;
    task_ = task.name();
    previous_task_ = find_task_plugin(task_);
    TaskPlugin plugin;
    plugin.read_task = [task](ConfigReader&) { return task; };
    register_task_plugin(task_, std::move(plugin));
  }
  if (parts.meta_objective) {
    const auto objective = parts.meta_objective;
    objective_task_ = task_name;
    objective_kind_ = objective->name();
    if (const auto plugin = find_task_plugin(task_name))
      if (MetaObjectiveReader r = reader_of(*plugin, objective_kind_)) previous_objective_ = std::move(r);
    // std::logic_error (a RuntimeError) when the task is unknown: the config reader's message,
    // which lists the tasks, is better, so leave it to the build.
    if (find_task_plugin(task_name))
      register_meta_objective(task_name, objective_kind_,
                              [objective](ConfigReader&, const Task&, std::uint64_t) -> std::unique_ptr<MetaObjective> {
                                return std::make_unique<PythonMetaObjective>(*objective);
                              });
  }
}

ScopedParts::~ScopedParts() {
  try {
    if (!objective_kind_.empty()) {
      if (previous_objective_) register_meta_objective(objective_task_, objective_kind_, *previous_objective_);
      else unregister_meta_objective(objective_task_, objective_kind_);
    }
    if (!task_.empty()) {
      if (previous_task_) register_task_plugin(task_, *previous_task_);
      else unregister_task_plugin(task_);
    }
  } catch (...) {  // a destructor must not throw; the registry is then left as it is
  }
}

BuiltRun build_from_python(const py::dict& config, const PythonParts& parts, BuildScope scope) {
  toml::table table = table_from_dict(config);
  // A TOML config without [task] runs Rastrigin (docs/config.md); from Python that default would
  // silently replace the task the caller forgot to pass, so a run must name its task.
  if (!parts.task && !table.contains("task"))
    throw InputError("config: no task: pass task=qdmeta.Task(...) or give config['task'], a built-in task's table "
                     "such as {'name': 'rastrigin'}");
  if (parts.task) {
    require_key(subtable(table, "task"), "task", "name", parts.task->name());
    if (const toml::table* builtin = builtin_table(*parts.task)) take_builtin_table(subtable(table, "task"), *builtin);
  }
  if (parts.meta_objective) require_key(subtable(table, "meta_fitness"), "meta_fitness", "kind", parts.meta_objective->name());
  const ScopedParts registered(parts, task_name_of(table));
  return build_run(table, "<python>", {}, scope);
}

std::unique_ptr<ScopedParts> register_for_resume(const std::filesystem::path& dir, const PythonParts& parts) {
  const toml::table config = load_toml(dir / "config.toml");
  const std::string task = task_name_of(config);
  if (parts.task && parts.task->name() != task)
    throw py::value_error(fmt::format("{}: the run's task is '{}', but the task given is '{}'", dir.string(), task,
                                      parts.task->name()));
  if (!parts.task && !find_task_plugin(task))
    throw InputError(fmt::format("{}: the run's task '{}' is not a built-in one: pass it again, "
                                 "qdmeta.resume(out_dir, task=...)",
                                 dir.string(), task));
  if (parts.meta_objective) {
    const auto* m = config["meta_fitness"].as_table();
    const auto* kind = m ? (*m)["kind"].as_string() : nullptr;
    if (kind == nullptr || kind->get() != parts.meta_objective->name())
      throw py::value_error(fmt::format("{}: the run's meta_fitness.kind is '{}', but the meta-objective given is '{}'",
                                        dir.string(), kind ? kind->get() : std::string("(none)"),
                                        parts.meta_objective->name()));
  }
  return std::make_unique<ScopedParts>(parts, task);
}

}  // namespace qdmeta::python
