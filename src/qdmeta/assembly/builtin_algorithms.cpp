#include "qdmeta/assembly/builtin_algorithms.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/build_cma_mae.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/assembly/cvt_centroids.hpp"
#include "qdmeta/assembly/memory_estimate.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/centroid_text.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

constexpr EnumNames<CmaBoundsHandling, 3> kCmaBoundsNames{{{CmaBoundsHandling::kNone, "none"},
                                                          {CmaBoundsHandling::kClamp, "clamp"},
                                                          {CmaBoundsHandling::kResample, "resample"}}};

// cvt.centroids_file's centroids, read when a run is built (never for BuildScope::kTasksOnly).
std::shared_ptr<const RowMatrix> read_given_centroids(const std::string& file, const std::string& source,
                                                      const CvtMapElitesParams& p, const Task& task) {
  try {
    return std::make_shared<const RowMatrix>(read_centroid_text(file, p.kmeans.centroids, task.base_feature_size()));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: cvt.centroids_file = \"{}\": {}", source, file, e.what()));
  }
}

// MAP-Elites over a grid (the paper's, called directly) or an archive of a registered kind.
AlgorithmMaker build_map_elites(AlgorithmBuild& b) {
  ConfigReader me = b.root.table("map_elites");
  const MapElitesParams p = read_map_elites_table(me);
  add_map_elites_memory(b.built.memory, p, b.task);
  ConfigReader archive_table = b.root.table("archive");
  ConfigReader feature_map_table = b.root.table("feature_map");
  if (const std::string kind = read_archive_kind(b, archive_table); kind != "grid") {
    AnyArchive archive = read_archive(b, archive_table, kind);
    auto feature_map = read_feature_map(b, feature_map_table, archive_table, archive.dimensions());
    return [p, task = std::move(b.task), feature_map = std::move(feature_map), archive = std::move(archive),
            mutation = b.mutation, seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
      return std::make_unique<BasicMapElites<AnyArchive>>(p, std::move(task), std::move(feature_map),
                                                          std::move(archive), mutation, seed);
    };
  }
  GridArchiveParams grid = read_grid_table(archive_table);
  auto feature_map = read_feature_map(b, feature_map_table, archive_table, static_cast<Index>(grid.bins.size()));
  GridArchiveParams sized = grid;  // as MapElites makes its archive: solutions, no base features
  sized.solution_size = b.task.genotype_size();
  b.built.memory.add("the archive", "archive.bins (cells) x genes", grid_archive_bytes(sized));
  return [p, task = std::move(b.task), feature_map = std::move(feature_map), grid = std::move(grid),
          mutation = b.mutation, seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    return std::make_unique<MapElites>(p, std::move(task), std::move(feature_map), std::move(grid), mutation, seed);
  };
}

AlgorithmMaker build_cvt_map_elites(AlgorithmBuild& b) {
  ConfigReader me = b.root.table("map_elites");
  ConfigReader cvt = b.root.table("cvt");
  CvtTable table = read_cvt_table(cvt);
  CvtMapElitesParams& p = table.algorithm;
  p.map_elites = read_map_elites_table(me);
  refuse_table(b.root, "archive", "cvt-map-elites", "its archive has one cell per [cvt] centroid");
  refuse_table(b.root, "feature_map", "cvt-map-elites", "its measures are the task's base features");
  // The descriptors' centroids depend on every task setting (episode length, features ...).
  if (const auto* task_resolved = b.built.resolved["task"].as_table())
    table.centroids.task_key = fmt::format("{}-{:016x}", b.task.name(), config_fingerprint(*task_resolved));
  // Read only where written, so that the resolved config (and the checkpoint fingerprint) of
  // every run made before this key existed stays what it was.
  const std::string centroids_file = cvt.has("centroids_file") ? cvt.string("centroids_file", "") : "";
  add_cvt_map_elites_memory(b.built.memory, p, b.task);
  p.make_centroids = cvt_centroid_source(std::move(table.centroids), p.kmeans, b.task);
  return [p = std::move(p), task = std::move(b.task), mutation = b.mutation, seed = b.settings.seed, centroids_file,
          source = cvt.source()]() mutable -> std::unique_ptr<Algorithm> {
    if (!centroids_file.empty()) p.centroids = read_given_centroids(centroids_file, source, p, task);
    return std::make_unique<CvtMapElites>(std::move(p), std::move(task), mutation, seed);
  };
}

// qd_meta.bottom_level = "cma-mae": [emitters] and the thresholds on [archive] as "cma-mae" reads
// them; a generation of a map is one batch of every emitter, and [mutation] has nothing to vary.
void read_qd_meta_emitters(AlgorithmBuild& b, ConfigReader& archive, const GridArchiveParams& grid, QdMetaParams& p) {
  refuse_table(b.root, "mutation", "qd-meta", "with qd_meta.bottom_level = \"cma-mae\" its emitters make each batch");
  b.built.resolved.erase("mutation");  // build_run() recorded its defaults, which do not apply
  ConfigReader emitters = b.root.table("emitters");
  std::vector<double> ranges;
  for (std::size_t d = 0; d < grid.bins.size(); ++d) ranges.push_back(grid.upper_of(d) - grid.lower_of(d));
  p.emitters = read_cma_mae_emitters(emitters, archive, b.task, std::move(ranges));
  p.batch_size = Index{p.emitters.emitters} * p.emitters.emitter.batch_size;
  if (p.batch_size > 10'000'000)
    throw InputError(fmt::format("{}: emitters.count x emitters.batch_size = {} is above the 10^7 rows a map's "
                                 "generation may have",
                                 emitters.source(), p.batch_size));
}

// The paper's bottom level: the keys of qd_meta.bottom_level = "cma-mae" are refused by name.
void refuse_qd_meta_emitters(const ConfigReader& root, const ConfigReader& archive) {
  const char* why = "it is read only with qd_meta.bottom_level = \"cma-mae\"";
  refuse_table(root, "emitters", "qd-meta", why);
  for (const char* key : {"learning_rate", "threshold_min"})
    if (archive.has(key))
      throw InputError(fmt::format("{}: archive.{} does not apply to algorithm \"qd-meta\": {}", archive.source(), key, why));
}

AlgorithmMaker build_qd_meta(AlgorithmBuild& b) {
  ConfigReader q = b.root.table("qd_meta");
  QdMetaParams p;
  // Read only where written (as database_inputs below).
  if (q.has("bottom_level")) p.bottom_level = q.choice("bottom_level", p.bottom_level, kBottomLevelNames);
  const bool emitters = p.bottom_level == BottomLevel::kCmaMae;
  p.meta_population = q.integer(QdMetaParams::kMetaPopulation, p.meta_population);
  if (emitters && q.has("batch_size"))
    throw InputError(fmt::format("{}: qd_meta.batch_size does not apply with qd_meta.bottom_level = \"cma-mae\": a "
                                 "generation is emitters.count x emitters.batch_size rows per map",
                                 q.source()));
  if (!emitters) p.batch_size = q.integer(QdMetaParams::kBatchSize, p.batch_size);
  p.initial_population = q.integer(QdMetaParams::kInitialPopulation, p.initial_population);
  p.database_capacity = q.integer(QdMetaParams::kDatabaseCapacity, p.database_capacity);
  p.hidden = q.integer(QdMetaParams::kHidden, p.hidden);
  p.sigmoid_scale = q.number(QdMetaParams::kSigmoidScale, p.sigmoid_scale);
  // Read only where written (as cma_es.small_population below).
  if (q.has("database_inputs")) p.database_inputs = q.choice("database_inputs", p.database_inputs, kDatabaseInputsNames);
  ConfigReader cma = b.root.table("cma_es");
  p.cma_sigma = cma.number(QdMetaParams::kCmaSigma, p.cma_sigma);
  p.cma_bounds = cma.choice("bounds", p.cma_bounds, kCmaBoundsNames);
  p.frozen = cma.boolean("frozen", p.frozen);
  // Read only where written, so that the resolved config (and the checkpoint fingerprint) of
  // every run made before these keys existed stays what it was.
  if (cma.has("small_population"))
    p.cma_small_population = cma.choice("small_population", p.cma_small_population, kCmaSmallPopulationNames);
  p.count_meta_evaluations = b.settings.counts == BudgetCount::kAll;
  ConfigReader control = b.root.table("control");
  auto controller = read_controller(b, control);
  refuse_table(b.root, "feature_map", "qd-meta", "it evolves its own neural feature-maps ([qd_meta], [cma_es])");
  ConfigReader meta_fitness = b.root.table("meta_fitness");
  auto objective = read_meta_objective(b, meta_fitness);  // none while the config is only resolved
  if (objective)
    for (Task& t : objective->tasks()) b.built.evaluation_tasks.push_back(std::move(t));
  else if (!meta_fitness.resolving())
    throw InputError(fmt::format("{}: the [meta_fitness] reader made no meta-objective", meta_fitness.source()));
  ConfigReader archive_table = b.root.table("archive");
  // Read only where written: QD-Meta's resolved config (and so its checkpoints' fingerprint) stays
  // what it was before archives had kinds.
  if (const std::string kind = archive_table.has("kind") ? read_archive_kind(archive_table) : "grid"; kind != "grid")
    throw InputError(fmt::format("{}: archive.kind = \"{}\": qd-meta rebuilds its archives from the database as "
                                 "grids, so its archive kind is \"grid\"",
                                 archive_table.source(), kind));
  GridArchiveParams grid = read_grid_table(archive_table);
  if (emitters) read_qd_meta_emitters(b, archive_table, grid, p);
  else refuse_qd_meta_emitters(b.root, archive_table);
  add_qd_meta_memory(b.built.memory, p, grid, b.task, controller->max_generations());
  return [p, task = std::move(b.task), objective = std::move(objective), grid = std::move(grid), mutation = b.mutation,
          controller = std::move(controller), seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    return std::make_unique<QdMeta>(p, std::move(task), std::move(objective), std::move(grid), mutation,
                                    std::move(controller), seed);
  };
}

AlgorithmMaker build_aurora(AlgorithmBuild& b) {
  ConfigReader a = b.root.table("aurora");
  const AuroraParams p = read_aurora_table(a);
  refuse_table(b.root, "archive", "aurora", "its archive is unstructured, sized by [aurora] target_size");
  refuse_table(b.root, "feature_map", "aurora", "its autoencoder learns the descriptors");
  add_aurora_memory(b.built.memory, p, b.task);
  return [p, task = std::move(b.task), mutation = b.mutation, seed = b.settings.seed,
          source = a.source()]() mutable -> std::unique_ptr<Algorithm> {
    try {
      return std::make_unique<Aurora>(p, std::move(task), mutation, seed);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", source, e.what()));
    }
  };
}

}  // namespace

std::vector<std::pair<std::string, AlgorithmBuilder>> builtin_algorithms() {
  return {{"map-elites", build_map_elites},
          {"qd-meta", build_qd_meta},
          {"cvt-map-elites", build_cvt_map_elites},
          {"aurora", build_aurora},
          {"cma-me", build_cma_me},
          {"cma-mae", build_cma_mae}};
}

}  // namespace qdmeta
