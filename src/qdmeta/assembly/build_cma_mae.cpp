#include "qdmeta/assembly/build_cma_mae.hpp"

#include <fmt/format.h>

#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/algorithms/cma_mae.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/assembly/cvt_centroids.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/iso_line_emitter.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

enum class EmitterArchiveKind { kGrid, kCvt };
constexpr EnumNames<EmitterArchiveKind, 2> kEmitterArchiveKindNames{
    {{EmitterArchiveKind::kGrid, "grid"}, {EmitterArchiveKind::kCvt, "cvt"}}};
// Genes live in [0, 1] (core/task.hpp): CMA-ES's candidates are kept there.
constexpr EnumNames<CmaBoundsHandling, 2> kGeneBoundsNames{
    {{CmaBoundsHandling::kResample, "resample"}, {CmaBoundsHandling::kClamp, "clamp"}}};

// The rules each algorithm name starts from.
struct EmitterDefaults {
  EmitterRanker ranker;
  EmitterSelection selection;
  EmitterRestart restart;
};
constexpr EmitterDefaults kCmaMeDefaults{EmitterRanker::kTwoStageImprovement, EmitterSelection::kFilter,
                                         EmitterRestart::kNoImprovement};
constexpr EmitterDefaults kCmaMaeDefaults{EmitterRanker::kImprovement, EmitterSelection::kMu, EmitterRestart::kBasic};

// Refuses each of `keys` present in [emitters]: they belong to other kinds than `kind`.
void refuse_other_kinds_keys(const ConfigReader& e, std::initializer_list<const char*> keys, EmitterKind kind,
                             std::string_view theirs) {
  for (const char* key : keys)
    if (e.has(key))
      throw InputError(fmt::format("{}: emitters.{} applies only to kind = {} (here \"{}\")", e.source(), key, theirs,
                                   to_string(kind)));
}

// The evolution-strategy emitters' keys: pyribs's EvolutionStrategyEmitter arguments.
void read_evolution_strategy_keys(ConfigReader& e, const EmitterDefaults& d, EvolutionStrategyEmitterParams& es) {
  es.sigma0 = e.number(EvolutionStrategyEmitterParams::kSigma0, es.sigma0);
  es.ranker = e.choice("ranker", d.ranker, kEmitterRankerNames);
  es.selection = e.choice("selection_rule", d.selection, kEmitterSelectionNames);
  es.restart = e.choice("restart_rule", d.restart, kEmitterRestartNames);
  if (es.restart == EmitterRestart::kEveryN)
    es.restart_every = static_cast<int>(e.integer(EvolutionStrategyEmitterParams::kRestartEvery, 100));
  else if (e.has("restart_every"))
    throw InputError(fmt::format("{}: emitters.restart_every applies only to restart_rule = \"every-n\" (here \"{}\")",
                                 e.source(), to_string(es.restart)));
  es.bounds = e.choice("bounds", CmaBoundsHandling::kResample, kGeneBoundsNames);
  if (e.has("es")) es.es = e.choice("es", EvolutionStrategyKind::kCmaEs, kEvolutionStrategyKindNames);
}

// [emitters]: every emitter the same, of one kind; genes are kept in [0, 1].
CmaMaeParams read_emitters_table(ConfigReader& e, const Task& task, const EmitterDefaults& d) {
  CmaMaeParams p;
  EvolutionStrategyEmitterParams& es = p.emitter;
  // kind, es and add_mode are written only when given: the resolved configs (fingerprints) and
  // checkpoints of runs made before these keys existed stay as they were.
  if (e.has("kind")) p.kind = e.choice("kind", p.kind, kEmitterKindNames);
  p.emitters = static_cast<int>(e.integer(CmaMaeParams::kCount, p.emitters));
  if (e.has("add_mode")) p.add_mode = e.choice("add_mode", p.add_mode, kAddModeNames);
  es.batch_size = static_cast<int>(e.integer(kEmitterBatchSize, es.batch_size));
  es.x0.assign(static_cast<std::size_t>(task.genotype_size()), e.number(CmaMaeParams::kX0, 0.5));
  const auto es_keys = {"sigma0", "ranker", "selection_rule", "restart_rule", "restart_every", "bounds", "es"};
  switch (p.kind) {
    case EmitterKind::kEvolutionStrategy:
      refuse_other_kinds_keys(e, {"sigma"}, p.kind, "\"gaussian\"");
      refuse_other_kinds_keys(e, {"iso_sigma", "line_sigma"}, p.kind, "\"iso-line\"");
      read_evolution_strategy_keys(e, d, es);
      break;
    case EmitterKind::kGaussian:
      refuse_other_kinds_keys(e, es_keys, p.kind, "\"evolution-strategy\"");
      refuse_other_kinds_keys(e, {"iso_sigma", "line_sigma"}, p.kind, "\"iso-line\"");
      p.sigma = e.number(GaussianEmitterParams::kSigma, p.sigma);
      es.bounds = CmaBoundsHandling::kClamp;
      break;
    case EmitterKind::kIsoLine:
      refuse_other_kinds_keys(e, es_keys, p.kind, "\"evolution-strategy\"");
      refuse_other_kinds_keys(e, {"sigma"}, p.kind, "\"gaussian\"");
      p.iso_sigma = e.number(IsoLineEmitterParams::kIsoSigma, p.iso_sigma);
      p.line_sigma = e.number(IsoLineEmitterParams::kLineSigma, p.line_sigma);
      es.bounds = CmaBoundsHandling::kClamp;
      break;
  }
  es.lower_bound = 0.0;
  es.upper_bound = 1.0;
  return p;
}

// The learning rate and threshold_min, on [archive] as on pyribs's archives; CMA-ME's are fixed.
void read_thresholds(ConfigReader& archive, const std::string& name, const Task& task, ThresholdParams& t) {
  if (name == "cma-mae") {
    t.alpha = archive.number(ThresholdParams::kLearningRate, 0.01);
    t.threshold_min = archive.number(ThresholdParams::kThresholdMin, task.qd_offset());
    return;
  }
  for (const char* key : {"learning_rate", "threshold_min"})
    if (archive.has(key))
      throw InputError(fmt::format("{}: archive.{} does not apply to algorithm \"cma-me\" (learning rate 1, "
                                   "threshold_min -inf): use algorithm = \"cma-mae\"",
                                   archive.source(), key));
}

AlgorithmMaker build_on_grid(AlgorithmBuild& b, CmaMaeParams p, ConfigReader& archive) {
  refuse_table(b.root, "cvt", p.name, "archive.kind = \"grid\" has no centroids");
  GridArchiveParams grid = read_grid_table(archive);
  ConfigReader feature_map_table = b.root.table("feature_map");
  auto feature_map = read_feature_map_table(feature_map_table, archive, b.task.base_feature_size(),
                                            static_cast<Index>(grid.bins.size()));
  grid.solution_size = b.task.genotype_size();
  grid.qd_offset = b.task.qd_offset();
  for (std::size_t d = 0; d < grid.bins.size(); ++d) p.emitter.measure_ranges.push_back(grid.upper_of(d) - grid.lower_of(d));
  b.built.memory.add("the archive", "archive.bins (cells) x genes", grid_archive_bytes(grid));
  add_cma_mae_memory(b.built.memory, p, grid_cells(grid), b.task);
  return [p = std::move(p), task = std::move(b.task), feature_map = std::move(feature_map), grid = std::move(grid),
          seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    auto make = [grid](Evaluator*) { return GridArchive(grid); };
    return std::make_unique<CmaMae<GridArchive>>(std::move(p), std::move(task), std::move(feature_map), make, seed);
  };
}

AlgorithmMaker build_on_cvt(AlgorithmBuild& b, CmaMaeParams p) {
  refuse_table(b.root, "feature_map", p.name, "with archive.kind = \"cvt\" its measures are the task's base features");
  ConfigReader cvt = b.root.table("cvt");
  CvtCentroidTable table = read_cvt_centroids(cvt);
  // The descriptors' centroids depend on every task setting (as cvt-map-elites's).
  if (const auto* task_resolved = b.built.resolved["task"].as_table())
    table.settings.task_key = fmt::format("{}-{:016x}", b.task.name(), config_fingerprint(*task_resolved));
  const Index genes = b.task.genotype_size(), features = b.task.base_feature_size();
  const auto cells = static_cast<double>(table.kmeans.centroids);
  b.built.memory.add("the archive", "cvt.centroids x (genes + base features)",
                     cells * (5 + static_cast<double>(sizeof(Real) * (genes + 2 * features))));
  b.built.memory.add("k-means's points", "cvt.samples x base features",
                     static_cast<double>(table.kmeans.samples) * static_cast<double>(sizeof(Real) * features + 12));
  add_cma_mae_memory(b.built.memory, p, cells, b.task);
  p.emitter.measure_ranges.assign(static_cast<std::size_t>(features), 1.0);  // base features are in [0, 1]
  std::vector<int> all(static_cast<std::size_t>(features));
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  auto identity = std::make_unique<SelectFeatureMap>(features, std::move(all));
  CentroidSource centroids = cvt_centroid_source(std::move(table.settings), table.kmeans, b.task);
  return [p = std::move(p), task = std::move(b.task), identity = std::move(identity), centroids = std::move(centroids),
          seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    const CvtArchiveParams shape{task.genotype_size(), task.qd_offset(), 0};  // no neighbour lists: no parents
    auto make = [shape, centroids](Evaluator* workers) { return CvtArchive(shape, centroids(workers)); };
    return std::make_unique<CmaMae<CvtArchive>>(std::move(p), std::move(task), std::move(identity), make, seed);
  };
}

AlgorithmMaker build_emitter_algorithm(AlgorithmBuild& b, const std::string& name, const EmitterDefaults& defaults) {
  refuse_table(b.root, "mutation", name, "its emitters' CMA-ES make each batch ([emitters])");
  // build_run() recorded [mutation]'s defaults before this builder ran: they do not apply here,
  // and the resolved config must run again as it is.
  b.built.resolved.erase("mutation");
  refuse_table(b.root, "map_elites", name, "its emitters make each batch ([emitters]) from x0, with no initial population");
  ConfigReader emitters = b.root.table("emitters");
  CmaMaeParams p = read_emitters_table(emitters, b.task, defaults);
  p.name = name;
  ConfigReader archive = b.root.table("archive");
  const EmitterArchiveKind kind = archive.choice("kind", EmitterArchiveKind::kGrid, kEmitterArchiveKindNames);
  read_thresholds(archive, name, b.task, p.thresholds);
  naming_source(emitters, [&] { p.validate(); });
  return kind == EmitterArchiveKind::kGrid ? build_on_grid(b, std::move(p), archive) : build_on_cvt(b, std::move(p));
}

}  // namespace

AlgorithmMaker build_cma_me(AlgorithmBuild& build) { return build_emitter_algorithm(build, "cma-me", kCmaMeDefaults); }

AlgorithmMaker build_cma_mae(AlgorithmBuild& build) { return build_emitter_algorithm(build, "cma-mae", kCmaMaeDefaults); }

CmaMaeParams read_cma_mae_emitters(ConfigReader& emitters, ConfigReader& archive, const Task& task,
                                   std::vector<double> measure_ranges) {
  CmaMaeParams p = read_emitters_table(emitters, task, kCmaMaeDefaults);
  read_thresholds(archive, "cma-mae", task, p.thresholds);
  p.emitter.measure_ranges = std::move(measure_ranges);
  naming_source(emitters, [&] { p.validate(); });
  return p;
}

}  // namespace qdmeta
