#include "qdmeta/experiment/build.hpp"

#include <fmt/format.h>

#include <limits>

#include "qdmeta/algorithms/map_elites.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/featuremap/select_feature_map.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();

enum class AlgorithmKind { kMapElites };
constexpr EnumNames<AlgorithmKind, 1> kAlgorithmNames{{{AlgorithmKind::kMapElites, "map-elites"}}};

enum class TaskKind { kRastrigin };
constexpr EnumNames<TaskKind, 1> kTaskNames{{{TaskKind::kRastrigin, "rastrigin"}}};

Task read_task(ConfigReader& t) {
  switch (t.choice("name", TaskKind::kRastrigin, kTaskNames)) {
    case TaskKind::kRastrigin: {
      RastriginParams p;
      p.dimensions = static_cast<int>(t.integer("dimensions", p.dimensions, 1, 10000));
      p.score_m = t.number("score_m", p.score_m, 1e-9, 1e300);
      return Task(RastriginTask(p));
    }
  }
  throw InputError("unreachable task kind");
}

MutationParams read_mutation(ConfigReader& m) {
  MutationParams p;
  p.kind = m.choice("kind", p.kind, kMutationKindNames);
  p.rate = m.number("rate", p.rate, 0.0, 1.0);
  p.sigma = m.number("sigma", p.sigma, 1e-12, 1e6);
  p.step = m.number("step", p.step, 1e-6, 1.0);
  p.validate();
  return p;
}

GridArchiveParams read_grid(ConfigReader& a, std::vector<int>& measures, Index base_features) {
  GridArchiveParams p;
  const auto bins = a.integers("bins", {100, 100}, 1, 100'000'000, 1, 16);
  p.bins.assign(bins.begin(), bins.end());
  p.lower = a.number("lower", p.lower, -1e300, 1e300);
  p.upper = a.number("upper", p.upper, -1e300, 1e300);
  std::vector<std::int64_t> fallback;
  for (std::size_t i = 0; i < bins.size(); ++i) fallback.push_back(static_cast<std::int64_t>(i));
  const auto m = a.integers("measures", fallback, 0, std::max<Index>(base_features - 1, 0), bins.size(), bins.size());
  measures.assign(m.begin(), m.end());
  p.solution_size = 1;  // completed by the algorithm from the task
  try {
    p.validate();
  } catch (const InputError& e) {
    throw InputError(a.source() + ": " + e.what());
  }
  return p;
}

}  // namespace

BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides) {
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

  ConfigReader task_table = root.table("task");
  Task task = read_task(task_table);
  ConfigReader mutation_table = root.table("mutation");
  const MutationParams mutation = read_mutation(mutation_table);

  switch (kind) {
    case AlgorithmKind::kMapElites: {
      ConfigReader me = root.table("map_elites");
      MapElitesParams p;
      p.batch_size = me.integer("batch_size", p.batch_size, 1, 10'000'000);
      p.initial_population = me.integer("initial_population", p.initial_population, 1, 100'000'000);
      ConfigReader archive_table = root.table("archive");
      std::vector<int> measures;
      GridArchiveParams grid = read_grid(archive_table, measures, task.base_feature_size());
      auto feature_map = std::make_unique<SelectFeatureMap>(task.base_feature_size(), measures);
      me.finish();
      archive_table.finish();
      built.algorithm = std::make_unique<MapElites>(p, std::move(task), std::move(feature_map), std::move(grid),
                                                    mutation, s.seed);
      break;
    }
  }
  budget.finish();
  log.finish();
  task_table.finish();
  mutation_table.finish();
  root.finish();
  return built;
}

}  // namespace qdmeta
