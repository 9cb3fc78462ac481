#pragma once
// The parts inside an algorithm that a config names by kind, beside tasks (task_registry.hpp) and
// algorithms (plugin/algorithm_registry.hpp): variation operators ([mutation] kind),
// controllers of G ([control] kind), feature-maps ([feature_map] kind) and archives ([archive]
// kind). Each is a Registry (registry.hpp) of readers: a reader gets the part's config table
// (`kind` already read) and reads its own keys from it, so an unknown or misspelt key is refused
// as any other is; then it makes the part.
//
// Which algorithms take which part (docs/config.md): a variation operator serves every built-in
// algorithm; a controller, QD-Meta; a feature-map and an archive, MAP-Elites. The built-in kinds
// that are the library's fast paths ("gaussian", "discrete-step", "uniform-resample",
// "iso-line"; feature-map "select"; archive "grid") are not in these registries: a registered
// name must differ from them (a config that reads the table says so). The controllers "static" and "sarsa" register here as a user's do
// (assembly/core_plugins.cpp). Register at start-up, before building runs; a reader may be
// called from any thread, and a variation operator from several at once (QD-Meta varies its maps
// in parallel), so neither may share mutable state.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/archive/any_archive.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/core/memory_estimate.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/variation.hpp"
#include "qdmeta/featuremap/feature_map.hpp"
#include "qdmeta/plugin/registry.hpp"

namespace qdmeta {

class ConfigReader;

// [mutation] kind = NAME: the operator for offspring of `task`'s genotypes.
using VariationReader = std::function<VariationFunction(ConfigReader& mutation, const Task& task)>;
// [control] kind = NAME: how many generations each meta-generation runs.
using ControllerReader = std::function<std::unique_ptr<GenerationController>(ConfigReader& control)>;
// [feature_map] kind = NAME: from `base_features` base features to `target_features` target
// features (the archive's dimensions).
using FeatureMapReader =
    std::function<std::unique_ptr<FeatureMap>(ConfigReader& feature_map, Index base_features, Index target_features)>;

// What an archive made for a run must hold.
struct ArchiveShape {
  Index solution_size = 0;      // the task's genotype size
  Index base_feature_size = 0;  // what the task measures (an archive may keep them or not)
  double qd_offset = 0.0;       // the task's QD-score offset
};
// [archive] kind = NAME: an empty archive of `shape`; it adds what it will allocate to `memory`
// (checked against the machine's limit before anything is allocated; allocate in the archive's
// constructor, which the reader may call: a run is built only after the check).
using ArchiveReader = std::function<AnyArchive(ConfigReader& archive, const ArchiveShape& shape, MemoryEstimate& memory)>;

// The registries. Thread-safe; lookups return snapshots (Registry::find).
Registry<VariationReader>& variation_registry();
Registry<ControllerReader>& controller_registry();
Registry<FeatureMapReader>& feature_map_registry();
Registry<ArchiveReader>& archive_registry();

// Reads `kind` of `table`: one of `builtin` or a name in `registered` (`fallback` when absent);
// an unknown name is refused listing them all, and so is a registered name that is also built in.
// Returns the name.
std::string read_kind(ConfigReader& table, const std::vector<std::string>& builtin,
                      const std::vector<std::string>& registered, std::string_view fallback);

}  // namespace qdmeta
