// Are the rigid legs a stand-in for the authors' compliant ones? (docs/fidelity.md, RHex hexapod:
// "Rigid legs by default"). The same random controllers walk on flat ground and under each damage
// type (or, with envs=courses, on each obstacle course) with each leg model, and the program
// prints, per environment and model, the mean distance, the dead count and the episode cost, and
// the paired differences against the compliant model: mean and largest |difference|, the
// correlation of the distances, and how many controllers die under one model but not the other.
// The extra models (compliant legs with free plate limits; rigid legs with DART's collision
// detector, a control for how far one model drifts from itself) also give their correlation with
// the rigid default. Not a micro-benchmark: a plain program.
//   rhex_leg_models [count=50] [seed=3] [threads=2] [offset=paper|authors] [leg=1]
//                   [envs=damages|courses] [free_limits=1|0] [detector_control=1|0]
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/paired_stats.hpp"

namespace {

using namespace qdmeta;
using qdmeta::bench::correlation;

struct Model {
  std::string name;
  rhex::LegModel legs;
  bool limits;
  rhex::CollisionKind collision = rhex::CollisionKind::kBullet;
};

struct Outcome {
  std::vector<double> distance;  // 0 when dead
  std::vector<int> dead;
  double seconds_per_episode = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{
      {"count", "50"}, {"seed", "3"},   {"threads", "2"},         {"offset", "paper"},
      {"leg", "1"},    {"envs", "damages"}, {"free_limits", "1"}, {"detector_control", "1"}};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    if (eq == std::string::npos || !args.contains(a.substr(0, eq))) {
      fmt::print(stderr, "rhex_leg_models: bad argument '{}' (key=value, keys: count seed threads offset leg envs "
                         "free_limits detector_control)\n", a);
      return 2;
    }
    args[a.substr(0, eq)] = a.substr(eq + 1);
  }
  try {
    const Index count = std::stoll(args["count"]);
    const int leg = std::stoi(args["leg"]);
    const int threads = std::stoi(args["threads"]);
    Rng rng(std::stoull(args["seed"]));
    RowMatrix g(count, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    std::vector<Model> models{{"rigid", rhex::LegModel::kRigid, true}, {"compliant", rhex::LegModel::kCompliant, true}};
    if (args["free_limits"] != "0") models.push_back({"compliant, free plate limits", rhex::LegModel::kCompliant, false});
    // The same rigid robot with another collision detector: how far two runs of one model drift
    // apart in an environment, the floor under which a leg-model difference cannot be read.
    if (args["detector_control"] != "0")
      models.push_back({"rigid, DART's detector", rhex::LegModel::kRigid, true, rhex::CollisionKind::kDart});
    std::vector<std::pair<std::string, rhex::RhexEnvironment>> envs{{"flat", {}}};
    if (args["envs"] == "courses") {
      for (const auto& [course, name] : rhex::kObstacleCourseNames)
        if (course != rhex::ObstacleCourse::kFlat) envs.emplace_back(std::string(name), rhex::RhexEnvironment::obstacle(course));
    } else if (args["envs"] == "damages") {
      for (auto d : {rhex::DamageType::kLegRemoval, rhex::DamageType::kLegShortening, rhex::DamageType::kBlockedHip,
                     rhex::DamageType::kPassiveHip})
        envs.emplace_back(fmt::format("{} leg {}", enum_to_string(rhex::kDamageTypeNames, d), leg),
                          rhex::RhexEnvironment::damaged(d, leg));
    } else {
      throw InputError("envs must be damages or courses, not '" + args["envs"] + "'");
    }
    auto evaluator = make_evaluator(threads);
    fmt::print("{} random controllers (seed {}), stance offset {}, {} threads; distance in m (dead = 0)\n", count,
               args["seed"], args["offset"], threads);
    for (const auto& [env_name, env] : envs) {
      std::vector<Outcome> outcomes;
      for (const auto& m : models) {
        RhexParams p;
        p.episode.legs = m.legs;
        p.episode.plate_joint_limits = m.limits;
        p.episode.collision = m.collision;
        p.stance_offset = enum_from_string(rhex::kStanceOffsetNames, "offset", args["offset"]);
        const RhexTask task(p);
        Outcome o;
        o.distance.resize(static_cast<std::size_t>(count));
        o.dead.resize(static_cast<std::size_t>(count));
        const auto start = std::chrono::steady_clock::now();
        evaluator->parallel_for(count, [&](Index i) {
          const rhex::EpisodeResult r = task.episode(g.row(i).data(), env);
          o.distance[static_cast<std::size_t>(i)] = r.dead ? 0.0 : r.fitness;
          o.dead[static_cast<std::size_t>(i)] = r.dead;
        });
        o.seconds_per_episode = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() *
                                threads / static_cast<double>(count);
        outcomes.push_back(std::move(o));
      }
      fmt::print("{}:\n", env_name);
      const Outcome& reference = outcomes[1];
      for (std::size_t k = 0; k < models.size(); ++k) {
        const Outcome& o = outcomes[k];
        double mean = 0, abs_diff = 0, max_diff = 0;
        int dead = 0, dead_disagree = 0;
        for (Index i = 0; i < count; ++i) {
          const auto j = static_cast<std::size_t>(i);
          mean += o.distance[j] / static_cast<double>(count);
          const double d = std::abs(o.distance[j] - reference.distance[j]);
          abs_diff += d / static_cast<double>(count);
          max_diff = std::max(max_diff, d);
          dead += o.dead[j];
          dead_disagree += o.dead[j] != reference.dead[j];
        }
        fmt::print("  {:30s} mean {:.3f}, dead {:3d}, {:.3f} s/episode/core", models[k].name, mean, dead,
                   o.seconds_per_episode);
        if (k != 1)
          fmt::print("; vs compliant: mean |diff| {:.3f}, max {:.3f}, r = {:.3f}, dead disagree {}", abs_diff, max_diff,
                     correlation(o.distance, reference.distance), dead_disagree);
        if (k > 1) fmt::print("; vs rigid: r = {:.3f}", correlation(o.distance, outcomes[0].distance));
        fmt::print("\n");
      }
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_leg_models: {}\n", e.what());
    return 2;
  }
  return 0;
}
