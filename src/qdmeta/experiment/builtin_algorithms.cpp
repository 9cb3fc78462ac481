#include "qdmeta/experiment/builtin_algorithms.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/algorithms/cvt_map_elites.hpp"
#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/control/controller.hpp"
#include "qdmeta/control/sarsa_control.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/algorithm_registry.hpp"
#include "qdmeta/experiment/checkpoint.hpp"
#include "qdmeta/experiment/memory_estimate.hpp"
#include "qdmeta/experiment/run_parts.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

constexpr EnumNames<CmaBoundsHandling, 3> kCmaBoundsNames{{{CmaBoundsHandling::kNone, "none"},
                                                          {CmaBoundsHandling::kClamp, "clamp"},
                                                          {CmaBoundsHandling::kResample, "resample"}}};

enum class ControlKind { kStatic, kSarsa };
constexpr EnumNames<ControlKind, 2> kControlNames{{{ControlKind::kStatic, "static"}, {ControlKind::kSarsa, "sarsa"}}};

// `measures` (which base features are the target features) is read when given a vector to
// fill: plain MAP-Elites has one, QD-Meta's feature-maps make their own.
GridArchiveParams read_grid(ConfigReader& a, std::vector<int>* measures, Index base_features) {
  GridArchiveParams p;
  const auto bins = a.integers("bins", {100, 100}, 1, 100'000'000, 1, 16);
  p.bins.assign(bins.begin(), bins.end());
  p.lower = a.number("lower", p.lower, -kNoUpper, kNoUpper);
  p.upper = a.number("upper", p.upper, -kNoUpper, kNoUpper);
  if (measures) {
    // Without `measures`, entry i of bins is base feature i: name bins, the key the user wrote.
    if (!a.has("measures") && static_cast<Index>(bins.size()) > base_features)
      throw InputError(fmt::format("{}: archive.bins has {} entries (one per target feature), but the task has {} "
                                   "base features: give at most {}, or archive.measures to pick a base feature for "
                                   "each",
                                   a.source(), bins.size(), base_features, base_features));
    std::vector<std::int64_t> fallback;
    for (std::size_t i = 0; i < bins.size(); ++i) fallback.push_back(static_cast<std::int64_t>(i));
    const auto m = a.integers("measures", fallback, 0, std::max<Index>(base_features - 1, 0), bins.size(), bins.size(),
                              "one per entry of bins, each a base-feature index");
    measures->assign(m.begin(), m.end());
  }
  p.solution_size = 1;  // completed by the algorithm from the task
  naming_source(a, [&] { p.validate(); });
  return p;
}

SarsaParams read_sarsa(ConfigReader& c) {
  SarsaParams p;
  p.actions = static_cast<int>(c.integer("actions", p.actions, 1, 1000));
  p.min_generations = static_cast<int>(c.integer("min_generations", p.min_generations, 1, 1'000'000));
  p.max_generations = static_cast<int>(c.integer("max_generations", p.max_generations, 1, 1'000'000));
  p.epsilon = c.number("epsilon", p.epsilon, 0.0, 1.0);
  p.gamma = c.number("gamma", p.gamma, 0.0, 1.0);
  p.alpha = c.number("alpha", p.alpha, 0.0, 1.0);
  p.alpha_zero_reward = c.number("alpha_zero_reward", p.alpha_zero_reward, 0.0, 1.0);
  p.trace_decay = c.number("trace_decay", p.trace_decay, 0.0, 1.0);
  p.trace_min = c.number("trace_min", p.trace_min, 0.0, 1.0);
  p.reward_scale = c.number("reward_scale", p.reward_scale, 0.0, kNoUpper, Open::kLower);
  p.reward_max = c.number("reward_max", p.reward_max, 0.0, kNoUpper, Open::kLower);
  StateTreeParams& t = p.tree;
  t.split_min_transitions = static_cast<std::size_t>(
      c.integer("split_min_transitions", static_cast<std::int64_t>(t.split_min_transitions), 2, 1'000'000'000));
  t.split_probability = c.number("split_probability", t.split_probability, 0.0, 1.0);
  t.split_min_fraction = c.number("split_min_fraction", t.split_min_fraction, 0.0, 0.5, Open::kBoth);
  t.max_candidates =
      static_cast<std::size_t>(c.integer("max_candidates", static_cast<std::int64_t>(t.max_candidates), 1, 1'000'000));
  t.min_value_gap = c.number("min_value_gap", t.min_value_gap, 0.0, kNoUpper);
  t.ks_alpha = c.number("ks_alpha", t.ks_alpha, 0.0, 1.0, Open::kBoth);
  return p;
}

MapElitesParams read_map_elites(ConfigReader& me) {
  MapElitesParams p;
  p.batch_size = me.integer("batch_size", p.batch_size, 1, 10'000'000);
  p.initial_population = me.integer("initial_population", p.initial_population, 1, 100'000'000);
  return p;
}

// The [cvt] table: how the centroids are made and cached.
CvtMapElitesParams read_cvt(ConfigReader& c) {
  CvtMapElitesParams p;
  KMeansParams& k = p.kmeans;
  k.centroids = c.integer("centroids", k.centroids, 1, 10'000'000);
  k.samples = c.integer("samples", k.samples, 1, 1'000'000'000);
  k.init = c.choice("init", k.init, kKMeansInitNames);
  k.init_samples = c.integer("init_samples", k.init_samples, 1, 1'000'000'000);
  k.method = c.choice("method", k.method, kKMeansMethodNames);
  k.iterations = static_cast<int>(c.integer("iterations", k.iterations, 0, 1'000'000));
  k.batch_size = c.integer("batch_size", k.batch_size, 1, 1'000'000'000);
  k.seed = static_cast<std::uint64_t>(c.integer("seed", static_cast<std::int64_t>(k.seed), 0, kMaxInt));
  const bool cache = c.boolean("cache", true);
  const std::string dir = c.string("cache_dir", "");
  if (cache) {
    p.cache_dir = dir.empty() ? default_centroid_cache_dir() : std::filesystem::path(dir);
    if (p.cache_dir.empty())
      throw InputError(fmt::format("{}: cvt.cache_dir is empty and neither XDG_CACHE_HOME nor HOME is set: "
                                   "give cvt.cache_dir or set cvt.cache = false", c.source()));
  }
  p.lookup_chunk = c.integer("lookup_chunk", p.lookup_chunk, 1, 1'000'000);
  p.search = c.choice("search", p.search, kCvtSearchNames);
  p.neighbours = c.integer("neighbours", p.neighbours, 1, 100'000);
  p.points = c.choice("points", p.points, kCvtPointsNames);
  if (p.points == CvtPoints::kRandomDescriptors)
    p.max_attempts = c.integer("max_attempts", p.max_attempts, 0, 1'000'000'000'000);
  try {
    p.kmeans.validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", c.source(), e.what()));
  }
  return p;
}

std::unique_ptr<GenerationController> read_control(ConfigReader& c) {
  switch (c.choice("kind", ControlKind::kSarsa, kControlNames)) {
    case ControlKind::kStatic:
      return std::make_unique<StaticControl>(static_cast<int>(c.integer("generations", 5, 1, 1'000'000)));
    case ControlKind::kSarsa:
      const SarsaParams p = read_sarsa(c);
      try {
        return std::make_unique<SarsaControl>(p);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", c.source(), e.what()));
      }
  }
  throw InputError("unreachable control kind");
}

// The [aurora] table (docs/specification.md, AURORA).
AuroraParams read_aurora(ConfigReader& a) {
  AuroraParams p;
  p.batch_size = a.integer("batch_size", p.batch_size, 1, 10'000'000);
  p.initial_population = a.integer("initial_population", p.initial_population, 1, 100'000'000);
  p.latent_size = a.integer("latent_size", p.latent_size, 1, 1'000);
  const auto hidden = a.integers("hidden", std::vector<std::int64_t>(p.hidden.begin(), p.hidden.end()), 1, 100'000, 1, 16);
  p.hidden.assign(hidden.begin(), hidden.end());
  p.learning_rate = a.number("learning_rate", p.learning_rate, 0.0, kNoUpper, Open::kLower);
  p.max_epochs = static_cast<int>(a.integer("max_epochs", p.max_epochs, 1, 100'000'000));
  p.max_training_rows = a.integer("max_training_rows", p.max_training_rows, 1, 100'000'000);
  p.target_size = a.integer("target_size", p.target_size, 1, 100'000'000);
  p.eps = a.number("eps", p.eps, 0.0, 0.999);
  p.novelty_neighbours = static_cast<int>(a.integer("novelty_neighbours", p.novelty_neighbours, 1, 1'000'000));
  p.size_control_gain = a.number("size_control_gain", p.size_control_gain, 0.0, 1.0);
  p.threshold_factor = a.number("threshold_factor", p.threshold_factor, 0.0, kNoUpper, Open::kLower);
  p.rebuild_every = static_cast<int>(a.integer("rebuild_every", p.rebuild_every, 1, 100'000'000));
  p.retrain_period_step = static_cast<int>(a.integer("retrain_period_step", p.retrain_period_step, 1, 100'000'000));
  p.retrain_period_max = static_cast<int>(a.integer("retrain_period_max", p.retrain_period_max, 1, 100'000'000));
  return p;
}

AlgorithmMaker build_map_elites(AlgorithmBuild& b) {
  ConfigReader me = b.root.table("map_elites");
  const MapElitesParams p = read_map_elites(me);
  ConfigReader archive_table = b.root.table("archive");
  std::vector<int> measures;
  GridArchiveParams grid = read_grid(archive_table, &measures, b.task.base_feature_size());
  auto feature_map = std::make_unique<SelectFeatureMap>(b.task.base_feature_size(), measures);
  GridArchiveParams sized = grid;  // as MapElites makes its archive: solutions, no base features
  sized.solution_size = b.task.genotype_size();
  b.built.memory.add("the archive", "archive.bins (cells) x genes", grid_archive_bytes(sized));
  add_map_elites_memory(b.built.memory, p, b.task);
  return [p, task = std::move(b.task), feature_map = std::move(feature_map), grid = std::move(grid),
          mutation = b.mutation, seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    return std::make_unique<MapElites>(p, std::move(task), std::move(feature_map), std::move(grid), mutation, seed);
  };
}

AlgorithmMaker build_cvt_map_elites(AlgorithmBuild& b) {
  ConfigReader me = b.root.table("map_elites");
  ConfigReader cvt = b.root.table("cvt");
  CvtMapElitesParams p = read_cvt(cvt);
  p.map_elites = read_map_elites(me);
  // The descriptors' centroids depend on every task setting (episode length, features ...).
  if (const auto* task_resolved = b.built.resolved["task"].as_table())
    p.task_key = fmt::format("{}-{:016x}", b.task.name(), config_fingerprint(*task_resolved));
  add_cvt_map_elites_memory(b.built.memory, p, b.task);
  return [p = std::move(p), task = std::move(b.task), mutation = b.mutation,
          seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    return std::make_unique<CvtMapElites>(std::move(p), std::move(task), mutation, seed);
  };
}

AlgorithmMaker build_qd_meta(AlgorithmBuild& b) {
  ConfigReader q = b.root.table("qd_meta");
  QdMetaParams p;
  p.meta_population = q.integer("meta_population", p.meta_population, 1, 10'000);
  p.batch_size = q.integer("batch_size", p.batch_size, 1, 10'000'000);
  p.initial_population = q.integer("initial_population", p.initial_population, 1, 100'000'000);
  p.database_capacity = q.integer("database_capacity", p.database_capacity, 1, 1'000'000'000);
  p.hidden = q.integer("hidden", p.hidden, 1, 10'000);
  p.sigmoid_scale = q.number("sigmoid_scale", p.sigmoid_scale, 0.0, kNoUpper, Open::kLower);
  ConfigReader cma = b.root.table("cma_es");
  p.cma_sigma = cma.number("sigma", p.cma_sigma, 0.0, kNoUpper, Open::kLower);
  p.cma_bounds = cma.choice("bounds", p.cma_bounds, kCmaBoundsNames);
  p.frozen = cma.boolean("frozen", p.frozen);
  p.count_meta_evaluations = b.settings.counts == BudgetCount::kAll;
  ConfigReader control = b.root.table("control");
  auto controller = read_control(control);
  ConfigReader meta_fitness = b.root.table("meta_fitness");
  auto objective = read_meta_objective(b, meta_fitness);
  for (Task& t : objective->tasks()) b.built.evaluation_tasks.push_back(std::move(t));
  ConfigReader archive_table = b.root.table("archive");
  GridArchiveParams grid = read_grid(archive_table, nullptr, b.task.base_feature_size());
  add_qd_meta_memory(b.built.memory, p, grid, b.task, controller->max_generations());
  return [p, task = std::move(b.task), objective = std::move(objective), grid = std::move(grid), mutation = b.mutation,
          controller = std::move(controller), seed = b.settings.seed]() mutable -> std::unique_ptr<Algorithm> {
    return std::make_unique<QdMeta>(p, std::move(task), std::move(objective), std::move(grid), mutation,
                                    std::move(controller), seed);
  };
}

AlgorithmMaker build_aurora(AlgorithmBuild& b) {
  ConfigReader a = b.root.table("aurora");
  const AuroraParams p = read_aurora(a);
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
          {"aurora", build_aurora}};
}

}  // namespace qdmeta
