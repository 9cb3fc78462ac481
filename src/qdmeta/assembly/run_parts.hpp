#pragma once
// Parts handed to build_run() as values: a program's (or the Python module's) own task,
// meta-objective, algorithm and variation operator, used without registering anything. The registries are only how
// a name in a config file finds a part; where a part is given, the config's name for it must be
// the part's (or absent: the resolved config then records the part's name), and the part is used.
#include <memory>
#include <optional>
#include <string>

#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/plugin/algorithm_builder.hpp"
#include "qdmeta/plugin/part_registries.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {

// A meta-objective: `read` makes one for a run from the rest of its [meta_fitness] table (each
// run owns its own), as a registered kind's reader does.
struct MetaObjectivePart {
  std::string kind;  // [meta_fitness] kind
  MetaObjectiveReader read;
};

// An algorithm: `build` is run through the builder protocol (algorithm_builder.hpp) as a
// registered builder is.
struct AlgorithmPart {
  std::string name;  // the config's `algorithm`
  AlgorithmBuilder build;
};

// A variation operator: `read` makes it for a run from the rest of its [mutation] table, as a
// registered kind's reader does (plugin/part_registries.hpp).
struct VariationPart {
  std::string kind;  // [mutation] kind
  VariationReader read;
};

struct RunParts {
  std::optional<Task> task;  // [task] then holds only its name
  std::optional<MetaObjectivePart> meta_objective;
  std::optional<AlgorithmPart> algorithm;
  std::optional<VariationPart> variation;
};

// The meta-objective of the run being built, for a builder that uses one (QD-Meta's): the part
// handed over, else the registered kind that [meta_fitness] names for the run's task.
std::unique_ptr<MetaObjective> read_meta_objective(AlgorithmBuild& build, ConfigReader& meta_fitness);

}  // namespace qdmeta
