#pragma once
// A run built from Python: the config dict goes through the same readers as a TOML file. A
// Python task and meta-objective are handed to build_run() as values (run_parts.hpp), nothing
// registered; the config is completed to name them ([task] name, [meta_fitness] kind). The run
// holds its own copies, so a later run or resume is handed them again.
#include <pybind11/pybind11.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <toml++/toml.h>

#include "python_meta_objective.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta::python {

// What Python hands over besides the config: a task and a meta-objective of its own (or none).
struct PythonParts {
  std::optional<Task> task;
  std::shared_ptr<const PythonMetaObjective> meta_objective;
};

// Fills in [task] name and [meta_fitness] kind from the parts (an explicit, different value is
// a ValueError), then builds the run with them handed over as values (run_parts.hpp).
BuiltRun build_from_python(const pybind11::dict& config, const PythonParts& parts, BuildScope scope = BuildScope::kRun);

// The parts a run in `dir` was made with (its config.toml names them), for open_for_resume():
// the task must have the name the run used, the meta-objective the kind.
RunParts parts_for_resume(const std::filesystem::path& dir, const PythonParts& parts);

}  // namespace qdmeta::python
