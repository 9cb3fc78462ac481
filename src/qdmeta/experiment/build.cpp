#include "qdmeta/experiment/build.hpp"

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
#include "qdmeta/experiment/checkpoint.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/memory_estimate.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"
#include "qdmeta/tasks/rastrigin/test_functions.hpp"

namespace qdmeta {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

enum class AlgorithmKind { kMapElites, kQdMeta, kCvtMapElites, kAurora };
constexpr EnumNames<AlgorithmKind, 4> kAlgorithmNames{{{AlgorithmKind::kMapElites, "map-elites"},
                                                       {AlgorithmKind::kQdMeta, "qd-meta"},
                                                       {AlgorithmKind::kCvtMapElites, "cvt-map-elites"},
                                                       {AlgorithmKind::kAurora, "aurora"}}};

constexpr EnumNames<CmaBoundsHandling, 3> kCmaBoundsNames{{{CmaBoundsHandling::kNone, "none"},
                                                          {CmaBoundsHandling::kClamp, "clamp"},
                                                          {CmaBoundsHandling::kResample, "resample"}}};

enum class ControlKind { kStatic, kSarsa };
constexpr EnumNames<ControlKind, 2> kControlNames{{{ControlKind::kStatic, "static"}, {ControlKind::kSarsa, "sarsa"}}};

enum class MetaFitnessKind { kDimension, kTranslation };
constexpr EnumNames<MetaFitnessKind, 2> kMetaFitnessNames{
    {{MetaFitnessKind::kDimension, "dimension"}, {MetaFitnessKind::kTranslation, "translation"}}};

enum class TaskKind { kRastrigin };
constexpr EnumNames<TaskKind, 1> kTaskNames{{{TaskKind::kRastrigin, "rastrigin"}}};

// Memory of the blocks an algorithm allocates (memory_estimate.hpp): floats are 4 bytes.
constexpr double kFloat = sizeof(Real);

double grid_cells(const GridArchiveParams& g) {
  double cells = 1;
  for (auto b : g.bins) cells *= static_cast<double>(b);
  return cells;
}

// One grid archive: per cell the objective, the occupied flag, the solution, the measures and
// the base features it keeps.
double grid_bytes(const GridArchiveParams& g, const Task& task, bool keeps_base) {
  const double per_cell = kFloat + 1 + kFloat * static_cast<double>(task.genotype_size() + static_cast<Index>(g.bins.size()) +
                                                             (keeps_base ? task.base_feature_size() : 0));
  return grid_cells(g) * per_cell;
}

// A generation's genotypes and their evaluations (fitness, base features, validity).
double offspring_bytes(double rows, const Task& task) {
  return rows * kFloat * static_cast<double>(2 * task.genotype_size() + task.base_feature_size() + 2);
}

void add_map_elites_memory(MemoryEstimate& m, const MapElitesParams& p, const Task& task) {
  m.add("a generation's offspring", "max(map_elites.initial_population, map_elites.batch_size) x genes",
        offspring_bytes(static_cast<double>(std::max(p.initial_population, p.batch_size)), task));
}

Task read_task(ConfigReader& t) {
  // Tasks registered by optional components or users (task_registry.hpp) come first.
  std::string valid = "\"rastrigin\"";
  for (const auto& n : registered_task_names()) valid += fmt::format(", \"{}\"", n);
  const std::string name = t.string("name", enum_to_string(kTaskNames, TaskKind::kRastrigin), valid);
  if (const TaskPlugin* plugin = find_task_plugin(name)) return plugin->read_task(t);
  if (name != enum_to_string(kTaskNames, TaskKind::kRastrigin))
    throw InputError(fmt::format("{}: task.name = \"{}\" is not a valid choice: use one of {}{}", t.source(), name, valid,
                                 name == "rhex" ? " (this build has no RHex task: it needs DART)" : ""));
  switch (TaskKind::kRastrigin) {
    case TaskKind::kRastrigin: {
      RastriginParams p;
      p.dimensions = static_cast<int>(t.integer("dimensions", p.dimensions, 1, 10000));
      p.score_m = t.number("score_m", p.score_m, 0.0, kNoUpper, Open::kLower);
      return Task(RastriginTask(p));
    }
  }
  throw InputError("unreachable task kind");
}

MutationParams read_mutation(ConfigReader& m) {
  MutationParams p;
  p.kind = m.choice("kind", p.kind, kMutationKindNames);
  p.rate = m.number("rate", p.rate, 0.0, 1.0);
  p.sigma = m.number("sigma", p.sigma, 0.0, kNoUpper, Open::kLower);
  p.step = m.number("step", p.step, 0.0, 1.0, Open::kLower);
  try {
    p.validate();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", m.source(), e.what()));
  }
  return p;
}

// `measures` (which base features are the target features) is read when given a vector to
// fill: plain MAP-Elites has one, QD-Meta's feature-maps make their own.
GridArchiveParams read_grid(ConfigReader& a, std::vector<int>* measures, Index base_features) {
  GridArchiveParams p;
  const auto bins = a.integers("bins", {100, 100}, 1, 100'000'000, 1, 16);
  p.bins.assign(bins.begin(), bins.end());
  p.lower = a.number("lower", p.lower, -kNoUpper, kNoUpper);
  p.upper = a.number("upper", p.upper, -kNoUpper, kNoUpper);
  if (measures) {
    std::vector<std::int64_t> fallback;
    for (std::size_t i = 0; i < bins.size(); ++i) fallback.push_back(static_cast<std::int64_t>(i));
    const auto m = a.integers("measures", fallback, 0, std::max<Index>(base_features - 1, 0), bins.size(), bins.size(),
                              "one per entry of bins, each a base-feature index");
    measures->assign(m.begin(), m.end());
  }
  p.solution_size = 1;  // completed by the algorithm from the task
  try {
    p.validate();
  } catch (const InputError& e) {
    throw InputError(a.source() + ": " + e.what());
  }
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

// The meta-objective of the task. Random choices made once per replicate (the Dimension
// meta-fitness's dimensions) come from the seed and are written to the resolved config, so
// that the resolved file repeats the run.
std::unique_ptr<MetaObjective> read_meta_fitness(ConfigReader& m, const Task& task, std::uint64_t seed) {
  if (const TaskPlugin* plugin = find_task_plugin(task.name()); plugin && plugin->read_meta_fitness)
    return plugin->read_meta_fitness(m, task, seed);
  if (task.name() != "rastrigin")
    throw InputError(fmt::format("{}: task '{}' has no meta-fitness yet", m.source(), task.name()));
  RastriginMetaParams p;
  const MetaFitnessKind kind = m.choice("kind", MetaFitnessKind::kTranslation, kMetaFitnessNames);
  p.sample_fraction = m.number("sample_fraction", p.sample_fraction, 0.0, 1.0, Open::kLower);
  p.score_m = task.qd_offset() < 0 ? -task.qd_offset() : p.score_m;
  const auto n = task.genotype_size();
  switch (kind) {
    case MetaFitnessKind::kDimension: {
      p.dimension_count = static_cast<int>(m.integer("dimension_count", p.dimension_count, 1, n, "1 to N (task.dimensions)"));
      std::vector<std::int64_t> drawn;
      Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), 0xD1D1});
      for (int d : rastrigin::sample_dimensions(rng, static_cast<int>(n), p.dimension_count)) drawn.push_back(d);
      const auto given = m.integers("dimensions", drawn, 0, n - 1, static_cast<std::size_t>(p.dimension_count),
                                    static_cast<std::size_t>(p.dimension_count),
                                    "dimension_count distinct entries in [0, N)");
      std::vector<int> dims(given.begin(), given.end());
      try {
        p.validate();
        return std::make_unique<RastriginDimensionMeta>(p, dims);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", m.source(), e.what()));
      }
    }
    case MetaFitnessKind::kTranslation: {
      p.transform_repetitions = static_cast<int>(m.integer("transform_repetitions", p.transform_repetitions, 1, 1000));
      p.transform_per_solution = m.boolean("transform_per_solution", p.transform_per_solution);
      try {
        p.validate();
        return std::make_unique<RastriginTranslationMeta>(p);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", m.source(), e.what()));
      }
    }
  }
  throw InputError("unreachable meta-fitness kind");
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

}  // namespace

BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides,
                   BuildScope scope) {
  toml::table effective = config;
  // A run's own config.toml carries a [provenance] table; it describes, it does not configure,
  // so a resolved config can be run again as it is.
  effective.erase("provenance");
  if (overrides.seed) effective.insert_or_assign("seed", static_cast<std::int64_t>(*overrides.seed));
  if (overrides.evaluations) {
    if (!effective.contains("budget")) effective.insert("budget", toml::table{});
    if (auto* budget = effective["budget"].as_table()) budget->insert_or_assign("evaluations", *overrides.evaluations);
  }

  BuiltRun built;
  ConfigReader root(effective, source, built.resolved);
  RunSettings& s = built.settings;
  const AlgorithmKind kind = root.choice("algorithm", AlgorithmKind::kMapElites, kAlgorithmNames);
  s.algorithm = std::string(enum_to_string(kAlgorithmNames, kind));
  s.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0, kMaxInt));

  ConfigReader budget = root.table("budget");
  s.budget = budget.integer("evaluations", 1'000'000, 1, kMaxInt);
  s.counts = budget.choice("counts", BudgetCount::kBottom, kBudgetCountNames);
  ConfigReader log = root.table("log");
  s.log_every = log.integer("every", 0, 0, kMaxInt);
  if (s.log_every == 0) s.log_every = std::max<std::int64_t>(1, s.budget / 200);
  ConfigReader checkpoint = root.table("checkpoint");
  s.checkpoint_every = checkpoint.number("every_seconds", s.checkpoint_every, 0.0, 1e9);

  ConfigReader task_table = root.table("task");
  Task task = read_task(task_table);
  ConfigReader mutation_table = root.table("mutation");
  const MutationParams mutation = read_mutation(mutation_table);
  built.evaluation_tasks.push_back(task);
  const bool make = scope == BuildScope::kRun;
  // Before the algorithm allocates anything: a config that cannot fit names its keys.
  const auto check_memory = [&] {
    if (make) require_memory(built.memory, memory_limit(), source);
  };

  switch (kind) {
    case AlgorithmKind::kMapElites: {
      ConfigReader me = root.table("map_elites");
      const MapElitesParams p = read_map_elites(me);
      ConfigReader archive_table = root.table("archive");
      std::vector<int> measures;
      GridArchiveParams grid = read_grid(archive_table, &measures, task.base_feature_size());
      auto feature_map = std::make_unique<SelectFeatureMap>(task.base_feature_size(), measures);
      me.finish();
      archive_table.finish();
      built.memory.add("the archive", "archive.bins (cells) x genes", grid_bytes(grid, task, false));
      add_map_elites_memory(built.memory, p, task);
      check_memory();
      if (make)
        built.algorithm = std::make_unique<MapElites>(p, std::move(task), std::move(feature_map), std::move(grid),
                                                    mutation, s.seed);
      break;
    }
    case AlgorithmKind::kCvtMapElites: {
      ConfigReader me = root.table("map_elites");
      ConfigReader cvt = root.table("cvt");
      CvtMapElitesParams p = read_cvt(cvt);
      p.map_elites = read_map_elites(me);
      // The descriptors' centroids depend on every task setting (episode length, features ...).
      if (const auto* task_resolved = built.resolved["task"].as_table())
        p.task_key = fmt::format("{}-{:016x}", task.name(), config_fingerprint(*task_resolved));
      me.finish();
      cvt.finish();
      {
        const auto cells = static_cast<double>(p.kmeans.centroids);
        const auto nb = static_cast<double>(task.base_feature_size());
        const double lists = p.search == CvtSearch::kParentBound
                                 ? static_cast<double>(std::min(p.neighbours, p.kmeans.centroids)) * sizeof(Index)
                                 : 0.0;
        built.memory.add("the archive and its neighbour lists", "cvt.centroids x (genes + base features + cvt.neighbours)",
                         cells * (kFloat + 1 + kFloat * (static_cast<double>(task.genotype_size()) + 2 * nb) + lists));
        built.memory.add("k-means's points", "cvt.samples x base features",
                         static_cast<double>(p.kmeans.samples) * (kFloat * nb + sizeof(Index) + sizeof(float)) +
                             static_cast<double>(std::min(p.kmeans.init_samples, p.kmeans.samples)) * sizeof(Index));
        add_map_elites_memory(built.memory, p.map_elites, task);
      }
      check_memory();
      if (make) built.algorithm = std::make_unique<CvtMapElites>(std::move(p), std::move(task), mutation, s.seed);
      break;
    }
    case AlgorithmKind::kQdMeta: {
      ConfigReader q = root.table("qd_meta");
      QdMetaParams p;
      p.meta_population = q.integer("meta_population", p.meta_population, 1, 10'000);
      p.batch_size = q.integer("batch_size", p.batch_size, 1, 10'000'000);
      p.initial_population = q.integer("initial_population", p.initial_population, 1, 100'000'000);
      p.database_capacity = q.integer("database_capacity", p.database_capacity, 1, 1'000'000'000);
      p.hidden = q.integer("hidden", p.hidden, 1, 10'000);
      p.sigmoid_scale = q.number("sigmoid_scale", p.sigmoid_scale, 0.0, kNoUpper, Open::kLower);
      ConfigReader cma = root.table("cma_es");
      p.cma_sigma = cma.number("sigma", p.cma_sigma, 0.0, kNoUpper, Open::kLower);
      p.cma_bounds = cma.choice("bounds", p.cma_bounds, kCmaBoundsNames);
      p.frozen = cma.boolean("frozen", p.frozen);
      p.count_meta_evaluations = s.counts == BudgetCount::kAll;
      ConfigReader control = root.table("control");
      auto controller = read_control(control);
      ConfigReader meta_fitness = root.table("meta_fitness");
      auto objective = read_meta_fitness(meta_fitness, task, s.seed);
      for (Task& t : objective->tasks()) built.evaluation_tasks.push_back(std::move(t));
      ConfigReader archive_table = root.table("archive");
      GridArchiveParams grid = read_grid(archive_table, nullptr, task.base_feature_size());
      for (const ConfigReader* r : {&q, &cma, &control, &meta_fitness, &archive_table}) r->finish();
      {
        const auto lambda = static_cast<double>(p.meta_population);
        const auto n = static_cast<double>(task.genotype_size());
        const auto nb = static_cast<double>(task.base_feature_size());
        const auto* c = built.resolved["control"].as_table();
        const double g_max = static_cast<double>(
            c && (*c)["kind"].value_or<std::string>("") == "static" ? (*c)["generations"].value_or<std::int64_t>(1)
                                                                    : (c ? (*c)["max_generations"].value_or<std::int64_t>(1) : 1));
        const auto dims = static_cast<double>(grid.bins.size());
        const double k = static_cast<double>(p.hidden) * (nb + 1 + dims) + 1;  // the feature-map's weights
        built.memory.add("the meta-population's archives", "(qd_meta.meta_population + 1) x archive.bins (cells) x genes",
                         (lambda + 1) * grid_bytes(grid, task, true) + lambda * grid_cells(grid) * (16 + kFloat * dims));
        built.memory.add("the circular database", "qd_meta.database_capacity x (genes + 2 x base features)",
                         static_cast<double>(p.database_capacity) * kFloat * (n + 2 * nb + 1));
        built.memory.add("every map's offspring of one meta-generation",
                         "qd_meta.meta_population x qd_meta.batch_size x control.max_generations (or generations) x genes",
                         lambda * offspring_bytes(g_max * static_cast<double>(p.batch_size), task));
        built.memory.add("CMA-ES's matrices", "(qd_meta.hidden x (base features + target features + 1))^2",
                         4 * k * k * sizeof(double) + lambda * k * sizeof(double));
        built.memory.add("the initial population", "qd_meta.initial_population x genes",
                         offspring_bytes(static_cast<double>(p.initial_population), task));
      }
      check_memory();
      if (make)
        built.algorithm = std::make_unique<QdMeta>(p, std::move(task), std::move(objective), std::move(grid), mutation,
                                                 std::move(controller), s.seed);
      break;
    }
    case AlgorithmKind::kAurora: {
      ConfigReader a = root.table("aurora");
      const AuroraParams p = read_aurora(a);
      a.finish();
      {
        std::vector<double> widths{static_cast<double>(task.base_feature_size())};
        for (Index h : p.hidden) widths.push_back(static_cast<double>(h));
        widths.push_back(static_cast<double>(p.latent_size));
        for (auto h = p.hidden.rbegin(); h != p.hidden.rend(); ++h) widths.push_back(static_cast<double>(*h));
        widths.push_back(static_cast<double>(task.base_feature_size()));
        double weights = 0, units = 0;
        for (std::size_t i = 0; i + 1 < widths.size(); ++i) weights += (widths[i] + 1) * widths[i + 1];
        for (double w : widths) units += w;
        const double rows = static_cast<double>(std::min(p.max_training_rows, 2 * p.target_size));
        built.memory.add("the autoencoder's weights, gradients and Adam moments", "aurora.hidden, aurora.latent_size",
                         4 * weights * sizeof(double));
        built.memory.add("the autoencoder's activations over a training set",
                         "aurora.max_training_rows x (aurora.hidden widths)", 2 * rows * units * sizeof(double));
        built.memory.add("the archive", "aurora.target_size x (genes + base features)",
                         2 * static_cast<double>(p.target_size) *
                             kFloat * static_cast<double>(task.genotype_size() + task.base_feature_size() + p.latent_size + 2));
        built.memory.add("a generation's offspring", "max(aurora.initial_population, aurora.batch_size) x genes",
                         offspring_bytes(static_cast<double>(std::max(p.initial_population, p.batch_size)), task));
      }
      check_memory();
      try {
        if (make) built.algorithm = std::make_unique<Aurora>(p, std::move(task), mutation, s.seed);
      } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", a.source(), e.what()));
      }
      break;
    }
  }
  budget.finish();
  log.finish();
  checkpoint.finish();
  task_table.finish();
  mutation_table.finish();
  root.finish();
  s.fingerprint = config_fingerprint(built.resolved);
  return built;
}

namespace {

std::string quoted_list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += fmt::format("{}{}", out.empty() ? "" : ", ", n);
  return out.empty() ? "none" : out;
}

const std::vector<std::string>& rastrigin_tests() {
  static const std::vector<std::string> names{"dimension", "translation"};
  return names;
}

}  // namespace

std::unique_ptr<AdaptationTests> build_adaptation_tests(const toml::table& config, const std::string& source,
                                                        std::string_view test, std::uint64_t seed) {
  toml::table resolved;
  ConfigReader root(config, source, resolved);
  ConfigReader task_table = root.table("task");
  const Task task = read_task(task_table);
  if (const TaskPlugin* plugin = find_task_plugin(task.name())) {
    const auto& names = plugin->adaptation_tests;
    if (!plugin->read_adaptation_tests || names.empty())
      throw InputError(fmt::format("task '{}' has no test phase", task.name()));
    if (std::find(names.begin(), names.end(), test) == names.end())
      throw InputError(fmt::format("unknown test '{}' for task '{}': valid tests are {}{}", test, task.name(),
                                   quoted_list(names),
                                   plugin->generalisation_groups.empty() ? "" : ", generalisation"));
    return plugin->read_adaptation_tests(config, source, task, test, seed);
  }
  if (task.name() != "rastrigin")
    throw InputError(fmt::format("task '{}' has no test phase yet (qdmeta adapt knows Rastrigin's)", task.name()));
  const auto n = static_cast<int>(task.genotype_size());
  const double m = -task.qd_offset();  // Rastrigin's offset is -M
  if (test == "dimension") {
    // One stream for drawing the pairs, apart from the per-function search streams.
    Rng rng = Rng::stream(seed, {key(StreamKey::kTest), 0xD1D1'0000'0000'0000ULL});
    return std::make_unique<RastriginDimensionTests>(n, 120, rng, m);
  }
  if (test == "translation") return std::make_unique<RastriginTranslationTests>(n, m);
  throw InputError(fmt::format("unknown test '{}' for task '{}': valid tests are {}", test, task.name(),
                               quoted_list(rastrigin_tests())));
}

std::vector<std::unique_ptr<AdaptationTests>> build_generalisation_groups(const toml::table& config,
                                                                         const std::string& source, std::uint64_t seed) {
  toml::table resolved;
  ConfigReader root(config, source, resolved);
  ConfigReader task_table = root.table("task");
  const Task task = read_task(task_table);
  const TaskPlugin* plugin = find_task_plugin(task.name());
  if (plugin == nullptr || plugin->generalisation_groups.empty())
    throw InputError(fmt::format("task '{}' has no generalisation test: valid tests are {}", task.name(),
                                 quoted_list(plugin ? plugin->adaptation_tests : rastrigin_tests())));
  std::vector<std::unique_ptr<AdaptationTests>> groups;
  for (const auto& name : plugin->generalisation_groups)
    groups.push_back(plugin->read_adaptation_tests(config, source, task, name, seed));
  return groups;
}

}  // namespace qdmeta
