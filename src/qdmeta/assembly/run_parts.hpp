#pragma once
// Parts handed to build_run() as values: a program's (or the Python module's) own task,
// meta-objective, algorithm, variation operator, controller, feature-map and archive, used
// without registering anything. The registries are only how a name in a config file finds a
// part; where a part is given, the config's name for it must be the part's (or absent: the
// resolved config then records the part's name), and the part is used: a part that the run's
// algorithm does not read (an archive handed to qd-meta) is refused. A part made from its table
// (all but a ready Task) reads its own keys there, as a registered kind does.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

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

// A task made from the rest of the run's [task] table (its own keys: task.joints), as a registered
// plugin's read_task does.
struct TaskPart {
  std::string name;  // [task] name
  std::function<Task(ConfigReader& task)> read;
};

// A controller of G (QD-Meta's [control]), a feature-map ([feature_map]) and an archive
// ([archive], MAP-Elites's): `read` is what a registered kind's reader is (plugin/part_registries.hpp).
// A feature-map or archive part may not be named as a built-in kind ("select", "grid").
struct ControllerPart {
  std::string kind;  // [control] kind
  ControllerReader read;
};
struct FeatureMapPart {
  std::string kind;  // [feature_map] kind
  FeatureMapReader read;
};
struct ArchivePart {
  std::string kind;  // [archive] kind
  ArchiveReader read;
};

struct RunParts {
  std::optional<Task> task;             // a ready task: [task] then holds only its name
  std::optional<TaskPart> task_reader;  // or one made from [task] (give one of the two)
  std::optional<MetaObjectivePart> meta_objective;
  std::optional<AlgorithmPart> algorithm;
  std::optional<VariationPart> variation;
  std::optional<ControllerPart> controller;
  std::optional<FeatureMapPart> feature_map;
  std::optional<ArchivePart> archive;
};

// For a builder (the built-in ones use these; a user's algorithm may): each reads a part's table
// through the part handed over, else through the built-in or registered kind the table names.
//
// The meta-objective of the run being built, for a builder that uses one (QD-Meta's): the part
// handed over, else the registered kind that [meta_fitness] names for the run's task.
std::unique_ptr<MetaObjective> read_meta_objective(AlgorithmBuild& build, ConfigReader& meta_fitness);
// [control]: the controller of G.
std::unique_ptr<GenerationController> read_controller(AlgorithmBuild& build, ConfigReader& control);
// [archive] kind: the part's name, else "grid" (the default) or a registered kind.
std::string read_archive_kind(AlgorithmBuild& build, ConfigReader& archive);
// [archive] of a kind other than "grid" (read_archive_kind's): the empty archive for the run's task.
AnyArchive read_archive(AlgorithmBuild& build, ConfigReader& archive, const std::string& kind);
// [feature_map]: from the task's base features to `targets` target features (the archive's
// dimensions); `archive` is the [archive] table ("select" reads its measures).
std::unique_ptr<FeatureMap> read_feature_map(AlgorithmBuild& build, ConfigReader& feature_map, ConfigReader& archive,
                                             Index targets);

// Reads `key` of `table` for a part handed over named `part_name`: absent, the part's name is
// recorded; any other name is refused ("... (the part handed over)"). Returns the name.
std::string read_part_name(ConfigReader& table, std::string_view key, const std::string& part_name);

}  // namespace qdmeta
