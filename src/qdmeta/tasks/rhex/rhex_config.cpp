#include "qdmeta/tasks/rhex/rhex_config.hpp"

#include <fmt/format.h>

#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {
namespace {

enum class RhexMetaKind { kDamage, kObstacle };
constexpr EnumNames<RhexMetaKind, 2> kRhexMetaNames{{{RhexMetaKind::kDamage, "damage"}, {RhexMetaKind::kObstacle, "obstacle"}}};

// Salts of the per-replicate draws (training damages, training courses).
constexpr std::uint64_t kDamageDraw = 0xDA3A6E, kCourseDraw = 0xC0025E;

template <class F>
auto naming_file(const ConfigReader& r, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", r.source(), e.what()));
  }
}

Task read_rhex_task(ConfigReader& t) {
  RhexParams p;
  p.features = t.choice("features", p.features, kRhexFeaturesNames);
  p.episode.duration = t.number("episode_seconds", p.episode.duration, 1e-3, 600.0);
  p.episode.time_step = t.number("time_step", p.episode.time_step, 1e-5, 0.1);
  p.episode.settle_steps = static_cast<int>(t.integer("settle_steps", p.episode.settle_steps, 0, 1'000'000));
  p.gene_step = t.number("gene_step", p.gene_step, 1e-6, 1.0);
  p.episode.legs = t.choice("legs", p.episode.legs, rhex::kLegModelNames);
  p.episode.collision = t.choice("collision", p.episode.collision, rhex::kCollisionKindNames);
  p.episode.lcp = t.choice("lcp", p.episode.lcp, rhex::kLcpSolverNames);
  p.environment.damage = t.choice("damage", p.environment.damage, rhex::kDamageTypeNames);
  p.environment.leg = static_cast<int>(t.integer("damaged_leg", p.environment.leg, 0, 5));
  p.environment.course = t.choice("course", p.environment.course, rhex::kObstacleCourseNames);
  return naming_file(t, [&] { return Task(RhexTask(p)); });
}

std::unique_ptr<MetaObjective> read_rhex_meta_fitness(ConfigReader& m, const Task& task, std::uint64_t seed) {
  const RhexTask* rhex_task = task.target<RhexTask>();
  if (rhex_task == nullptr) throw InputError(fmt::format("{}: the RHex meta-fitness needs the RHex task", m.source()));
  RhexParams params = rhex_task->params();
  params.environment = {};
  RhexMetaParams p;
  const RhexMetaKind kind = m.choice("kind", RhexMetaKind::kDamage, kRhexMetaNames);
  p.sample_fraction = m.number("sample_fraction", p.sample_fraction, 1e-9, 1.0);
  switch (kind) {
    case RhexMetaKind::kDamage: {
      const auto count = m.integer("damage_type_count", 2, 1, 4);
      Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), kDamageDraw});
      std::vector<std::int64_t> drawn;  // the paper's numbering: 1 removal, 2 shortening, 3 blocked, 4 passive
      for (rhex::DamageType d : draw_damage_types(rng, static_cast<int>(count))) drawn.push_back(static_cast<int>(d));
      const auto given = m.integers("damage_types", drawn, 1, 4, static_cast<std::size_t>(count), static_cast<std::size_t>(count));
      std::vector<rhex::DamageType> types;
      for (auto d : given) types.push_back(static_cast<rhex::DamageType>(d));
      return naming_file(m, [&] {
        return std::make_unique<RhexMetaFitness>("rhex-damage", p, RhexTask(params), damage_environments(types));
      });
    }
    case RhexMetaKind::kObstacle: {
      const auto count = m.integer("course_count", 5, 1, 9);
      Rng rng = Rng::stream(seed, {key(StreamKey::kMetaFitness), kCourseDraw});
      std::vector<std::int64_t> drawn;  // SPEC.md's numbering 1..9
      for (rhex::ObstacleCourse c : draw_courses(rng, static_cast<int>(count))) drawn.push_back(static_cast<int>(c));
      const auto given = m.integers("courses", drawn, 1, 9, static_cast<std::size_t>(count), static_cast<std::size_t>(count));
      std::vector<rhex::RhexEnvironment> envs;
      for (auto c : given) envs.push_back(rhex::RhexEnvironment::obstacle(static_cast<rhex::ObstacleCourse>(c)));
      return naming_file(m, [&] { return std::make_unique<RhexMetaFitness>("rhex-obstacle", p, RhexTask(params), envs); });
    }
  }
  throw InputError("unreachable RHex meta-fitness kind");
}

}  // namespace

void register_rhex_task() { register_task_plugin("rhex", {read_rhex_task, read_rhex_meta_fitness}); }

}  // namespace qdmeta
