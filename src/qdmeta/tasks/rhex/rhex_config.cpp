#include "qdmeta/tasks/rhex/rhex_config.hpp"

#include <fmt/format.h>

#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"
#include "qdmeta/tasks/rhex/rhex_adaptation.hpp"
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {
namespace {

enum class RhexMetaKind { kDamage, kObstacle };
constexpr EnumNames<RhexMetaKind, 2> kRhexMetaNames{{{RhexMetaKind::kDamage, "damage"}, {RhexMetaKind::kObstacle, "obstacle"}}};

// Salts of the per-replicate draws (training damages, training courses).
constexpr std::uint64_t kDamageDraw = 0xDA3A6E, kCourseDraw = 0xC0025E;

RhexParams read_rhex_params(ConfigReader& t) {
  RhexParams p;
  p.features = t.choice("features", p.features, kRhexFeaturesNames);
  p.episode.duration = t.number(rhex::EpisodeSettings::kEpisodeSeconds, p.episode.duration);
  p.episode.time_step = t.number(rhex::EpisodeSettings::kTimeStep, p.episode.time_step);
  p.episode.settle_steps = static_cast<int>(t.integer(rhex::EpisodeSettings::kSettleSteps, p.episode.settle_steps));
  p.gene_step = t.number(RhexParams::kGeneStep, p.gene_step);
  p.stance_offset = t.choice("stance_offset", p.stance_offset, rhex::kStanceOffsetNames);
  p.episode.engine = t.choice("engine", p.episode.engine, rhex::kEngineNames);
  p.episode.legs = t.choice("legs", p.episode.legs, rhex::kLegModelNames);
  p.episode.collision = t.choice("collision", p.episode.collision, rhex::kCollisionKindNames);
  p.episode.lcp = t.choice("lcp", p.episode.lcp, rhex::kLcpSolverNames);
  p.episode.plate_joint_limits = t.boolean("plate_joint_limits", p.episode.plate_joint_limits);
  p.environment.damage = t.choice("damage", p.environment.damage, rhex::kDamageTypeNames);
  p.environment.leg = static_cast<int>(t.integer(rhex::RhexEnvironment::kDamagedLeg, p.environment.leg));
  p.environment.course = t.choice("course", p.environment.course, rhex::kObstacleCourseNames);
  return p;
}

Task read_rhex_task(ConfigReader& t) {
  const RhexParams p = read_rhex_params(t);
  return naming_source(t, [&] { return Task(RhexTask(p)); });
}

TaskShape read_rhex_shape(ConfigReader& t) {
  const RhexParams p = read_rhex_params(t);
  naming_source(t, [&] { p.validate(); });  // what RhexTask's constructor checks
  return RhexTask::shape_of(p);
}

// [meta_fitness] of `kind` (its `kind` key is read by the task registry, or by the caller).
std::unique_ptr<MetaObjective> read_rhex_meta_fitness(ConfigReader& m, const Task& task, std::uint64_t seed,
                                                      RhexMetaKind kind) {
  // While resolving, `task` is only a shape: its keys read and checked, nothing is made.
  const RhexTask* rhex_task = task.target<RhexTask>();
  if (rhex_task == nullptr && !(m.resolving() && task.name() == "rhex"))
    throw InputError(fmt::format("{}: the RHex meta-fitness needs the RHex task", m.source()));
  RhexParams params = rhex_task != nullptr ? rhex_task->params() : RhexParams{};
  params.environment = {};
  RhexMetaParams p;
  p.sample_fraction = m.number(RhexMetaParams::kSampleFraction, p.sample_fraction);
  const auto make = [&](const char* name, std::vector<rhex::RhexEnvironment> envs) -> std::unique_ptr<MetaObjective> {
    return naming_source(m, [&]() -> std::unique_ptr<MetaObjective> {
      if (!m.resolving()) return std::make_unique<RhexMetaFitness>(name, p, RhexTask(params), std::move(envs));
      p.validate();  // what RhexMetaFitness's constructor checks
      for (const auto& e : envs) e.validate();
      return nullptr;
    });
  };
  // damage_type_count and course_count keep literal ranges: they land in no params struct (the
  // meta-fitness takes the drawn environments), so the reader is their only check.
  switch (kind) {
    case RhexMetaKind::kDamage: {
      const auto count = m.integer("damage_type_count", 2, 1, 4);
      Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), kDamageDraw});
      std::vector<std::int64_t> drawn;  // the paper's numbering: 1 removal, 2 shortening, 3 blocked, 4 passive
      for (rhex::DamageType d : draw_damage_types(rng, static_cast<int>(count))) drawn.push_back(static_cast<int>(d));
      const auto given = m.integers("damage_types", drawn, 1, 4, static_cast<std::size_t>(count),
                                    static_cast<std::size_t>(count), "damage_type_count entries in 1..4");
      std::vector<rhex::DamageType> types;
      for (auto d : given) types.push_back(static_cast<rhex::DamageType>(d));
      return make("rhex-damage", damage_environments(types));
    }
    case RhexMetaKind::kObstacle: {
      const auto count = m.integer("course_count", 5, 1, 9);
      Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), kCourseDraw});
      std::vector<std::int64_t> drawn;  // docs/specification.md's numbering 1..9
      for (rhex::ObstacleCourse c : draw_courses(rng, static_cast<int>(count))) drawn.push_back(static_cast<int>(c));
      const auto given = m.integers("courses", drawn, 1, 9, static_cast<std::size_t>(count),
                                    static_cast<std::size_t>(count), "course_count entries in 1..9");
      std::vector<rhex::RhexEnvironment> envs;
      for (auto c : given) envs.push_back(rhex::RhexEnvironment::obstacle(static_cast<rhex::ObstacleCourse>(c)));
      return make("rhex-obstacle", std::move(envs));
    }
  }
  throw InputError("unreachable RHex meta-fitness kind");
}

// The training environments of `kind` for the run of `config`: a QD-Meta run trained on that
// kind uses its own [meta_fitness] (the resolved config holds the drawn set); any other run
// (the other meta-fitness, a baseline) gets the paper's default draw from its seed, the same
// one a QD-Meta run of that kind and seed makes.
std::vector<rhex::RhexEnvironment> trained_environments(const toml::table& config, const std::string& source,
                                                        const Task& task, RhexMetaKind kind) {
  const auto seed = static_cast<std::uint64_t>(config["seed"].value_or<std::int64_t>(1));
  const bool qd_meta = config["algorithm"].value_or<std::string>("") == "qd-meta";
  const auto* own = config["meta_fitness"].as_table();
  toml::table table;
  if (qd_meta && own && (*own)["kind"].value_or<std::string>("damage") == enum_to_string(kRhexMetaNames, kind))
    table = *own;
  else
    table.insert("kind", std::string(enum_to_string(kRhexMetaNames, kind)));
  toml::table resolved;
  ConfigReader reader(table, source, resolved, "meta_fitness");
  const auto meta = read_rhex_meta_fitness(reader, task, seed, kind);
  return dynamic_cast<const RhexMetaFitness&>(*meta).environments();
}

// `qdmeta adapt` families. The --seed of adapt changes only the search orders: the partition
// into training and test environments belongs to the run.
std::unique_ptr<AdaptationTests> read_rhex_adaptation_tests(const toml::table& config, const std::string& source,
                                                            const Task& task, std::string_view test, std::uint64_t) {
  const RhexTask* rhex_task = task.target<RhexTask>();
  if (rhex_task == nullptr) throw InputError(fmt::format("{}: the RHex tests need the RHex task", source));
  RhexParams params = rhex_task->params();
  params.environment = {};
  const bool damage = test.starts_with("damage");
  const bool training = test.ends_with("-training");
  auto envs = trained_environments(config, source, task, damage ? RhexMetaKind::kDamage : RhexMetaKind::kObstacle);
  if (!training) envs = damage ? untrained_damage_environments(envs) : untrained_course_environments(envs);
  try {
    return std::make_unique<RhexAdaptationTests>(std::string(test), RhexTask(params), std::move(envs));
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()));
  }
}

}  // namespace

void register_rhex_task() {
  TaskPlugin plugin;
  plugin.read_task = read_rhex_task;
  plugin.read_shape = read_rhex_shape;
  // The first kind is the default.
  for (const RhexMetaKind kind : {RhexMetaKind::kDamage, RhexMetaKind::kObstacle})
    plugin.meta_objectives.emplace_back(std::string(enum_to_string(kRhexMetaNames, kind)),
                                        [kind](ConfigReader& m, const Task& task, std::uint64_t seed) {
                                          return read_rhex_meta_fitness(m, task, seed, kind);
                                        });
  plugin.read_adaptation_tests = read_rhex_adaptation_tests;
  plugin.adaptation_tests = {"damage", "obstacle", "damage-training", "obstacle-training"};
  plugin.generalisation_groups = {"damage-training", "obstacle-training", "damage", "obstacle"};
  register_task_plugin("rhex", std::move(plugin));
}

}  // namespace qdmeta
