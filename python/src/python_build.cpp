#include "python_build.hpp"

#include <fmt/format.h>

#include <sstream>
#include <string_view>

#include "configured_task.hpp"
#include "python_task.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"
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

// The parts build_run() takes as values: a Python task (a built-in one is its [task] table
// instead, filled in above) and a Python meta-objective, each run getting its own copy.
RunParts run_parts(const PythonParts& parts) {
  RunParts run;
  if (parts.task && is_python_task(*parts.task)) run.task = *parts.task;
  if (const auto objective = parts.meta_objective)
    run.meta_objective = MetaObjectivePart{
        objective->name(), [objective](ConfigReader&, const Task&, std::uint64_t) -> std::unique_ptr<MetaObjective> {
          return std::make_unique<PythonMetaObjective>(*objective);
        }};
  return run;
}

}  // namespace

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
  try {
    return build_run(table, "<python>", {}, run_parts(parts), scope);
  } catch (const InputError& e) {
    // The registry's message knows only [meta_fitness]; from Python the meta-fitness is an argument.
    if (parts.meta_objective || !std::string_view(e.what()).ends_with("has no meta-fitness yet")) throw;
    throw InputError(fmt::format("{}: pass meta_objective=qdmeta.MetaObjective(f, name=...)", e.what()));
  }
}

RunParts parts_for_resume(const std::filesystem::path& dir, const PythonParts& parts) {
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
  return run_parts(parts);
}

}  // namespace qdmeta::python
