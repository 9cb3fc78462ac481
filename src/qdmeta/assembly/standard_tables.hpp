#pragma once
// Readers of the config tables the built-in algorithms share, for an algorithm of a user's own
// to read them the same way (same keys, defaults, ranges and one-line errors; docs/config.md):
// its builder (algorithm_builder.hpp) calls them on tables of build.root. Each reads only its
// table's keys and leaves the unknown-key check to the builder protocol.
#include <memory>
#include <string>
#include <vector>

#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/assembly/cvt_centroids.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/featuremap/feature_map.hpp"
#include "qdmeta/plugin/part_registries.hpp"

namespace qdmeta {

class ConfigReader;

// [mutation]: a built-in kind with its parameters, or a registered one's operator
// (plugin/part_registries.hpp) in MutationParams::variation, made for `task`.
MutationParams read_mutation_table(ConfigReader& mutation, const Task& task);

// [map_elites]: batch_size, initial_population.
MapElitesParams read_map_elites_table(ConfigReader& map_elites);

// [archive] of kind "grid": bins, lower, upper (solution_size is left for the algorithm to set
// from its task).
GridArchiveParams read_grid_table(ConfigReader& archive);
// [archive] kind: "grid" (the default) or a registered archive.
std::string read_archive_kind(ConfigReader& archive);
// [archive] kind = NAME of the registry: the archive for `task`, its memory added to `memory`.
AnyArchive read_registered_archive(ConfigReader& archive, const std::string& kind, const Task& task,
                                   MemoryEstimate& memory);
// The same with `reader` (a part handed over, assembly/run_parts.hpp): what it made is checked
// (empty, the task's genes, a dimension) as a registered kind's archive is.
AnyArchive read_archive_with(ConfigReader& archive, const std::string& kind, const ArchiveReader& reader,
                             const Task& task, MemoryEstimate& memory);

// [feature_map] kind: "select" (the default: the target features are the base features that
// [archive] measures picks, one per target feature) or a registered feature-map, from the task's
// base features to `targets` target features. `archive` is the [archive] table (measures).
std::unique_ptr<FeatureMap> read_feature_map_table(ConfigReader& feature_map, ConfigReader& archive,
                                                   Index base_features, Index targets);
// A feature-map of kind `kind` made by `reader` (a registered kind's, or a part's), checked to map
// `base_features` to `targets`; archive.measures is refused (it is "select"'s key).
std::unique_ptr<FeatureMap> read_feature_map_with(ConfigReader& feature_map, const ConfigReader& archive,
                                                  const std::string& kind, const FeatureMapReader& reader,
                                                  Index base_features, Index targets);

// [control]: kind "sarsa" (the default), "static" or a registered controller.
std::unique_ptr<GenerationController> read_control_table(ConfigReader& control);
// A controller of kind `kind` made by `reader` (a registered kind's, or a part's); made, or refused.
std::unique_ptr<GenerationController> read_control_with(ConfigReader& control, const std::string& kind,
                                                        const ControllerReader& reader);
// The keys of kind "sarsa" and "static" (the two built-in controllers' readers).
SarsaParams read_sarsa_table(ConfigReader& control);
std::unique_ptr<GenerationController> read_sarsa_control(ConfigReader& control);
std::unique_ptr<GenerationController> read_static_control(ConfigReader& control);

// [cvt]'s keys that shape and cache the centroids (what any archive of CVT cells needs).
struct CvtCentroidTable {
  KMeansParams kmeans;
  CvtCentroidSettings settings;
};
CvtCentroidTable read_cvt_centroids(ConfigReader& cvt);
// [cvt]: the centroids, how they are made and cached, how offspring find their cells
// ([map_elites] is read separately).
struct CvtTable {
  CvtMapElitesParams algorithm;
  CvtCentroidSettings centroids;
};
CvtTable read_cvt_table(ConfigReader& cvt);
// [aurora].
AuroraParams read_aurora_table(ConfigReader& aurora);

// The kinds a config may name in each table: the built-in ones, then the registered ones (the
// top-level help lists them).
std::vector<std::string> mutation_kinds();
std::vector<std::string> archive_kinds();
std::vector<std::string> feature_map_kinds();
std::vector<std::string> control_kinds();

// InputError when `root` has table `name`, which `algorithm` does not read: `why` says what it
// does instead ("qd-meta evolves its own neural feature-maps").
void refuse_table(const ConfigReader& root, std::string_view name, std::string_view algorithm, std::string_view why);

}  // namespace qdmeta
