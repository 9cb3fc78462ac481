#pragma once
// A run built from Python: the config dict goes through the same readers as a TOML file. While
// it is built, a Python task is registered under its name (its [task] table is then just that
// name) and a Python meta-objective under its name as a [meta_fitness] kind of the run's task;
// the config is completed to select them. The registrations end with the build (the run holds
// its own copies), so a later run or resume must be handed them again.
#include <pybind11/pybind11.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <toml++/toml.h>

#include "python_meta_objective.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/experiment/build.hpp"
#include "qdmeta/experiment/task_registry.hpp"

namespace qdmeta::python {

// What Python hands over besides the config: a task and a meta-objective of its own (or none).
struct PythonParts {
  std::optional<Task> task;
  std::shared_ptr<const PythonMetaObjective> meta_objective;
};

// The parts registered for this object's life; then what was registered before under the same
// names comes back.
class ScopedParts {
 public:
  ScopedParts(const PythonParts& parts, const std::string& task_name);
  ~ScopedParts();
  ScopedParts(const ScopedParts&) = delete;
  ScopedParts& operator=(const ScopedParts&) = delete;

 private:
  std::string task_;                              // the Python task's name, empty when none
  std::shared_ptr<const TaskPlugin> previous_task_;
  std::string objective_task_, objective_kind_;   // the meta-objective's registration
  std::optional<MetaObjectiveReader> previous_objective_;
};

// Fills in [task] name and [meta_fitness] kind from the parts (an explicit, different value is
// a ValueError), then builds the run with them registered.
BuiltRun build_from_python(const pybind11::dict& config, const PythonParts& parts, BuildScope scope = BuildScope::kRun);

// The parts a run in `dir` was made with (its config.toml names them), registered while
// open_for_resume() rebuilds it: the task must have the name the run used, the
// meta-objective the kind.
std::unique_ptr<ScopedParts> register_for_resume(const std::filesystem::path& dir, const PythonParts& parts);

}  // namespace qdmeta::python
