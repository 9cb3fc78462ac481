// Why MuJoCo's RHex turns more than DART's (docs/fidelity.md, "RHex on MuJoCo"): the same random
// controllers on one environment in both engines, rigid legs. Per engine: mean |yaw| and |y| at the
// end of the walk, mean contact points per step, and the signed yaw's correlation and regression
// slope against DART (slope ~2 with high r: the same turn, amplified). Not a micro-benchmark.
//   rhex_turning [count=40] [seed=3] [threads=1] [course=flat] [seconds=5] [legs=rigid]
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/key_value_args.hpp"
#include "tasks/paired_stats.hpp"
#include "tasks/rhex_time_step.hpp"

namespace {

using namespace qdmeta;

double slope(const std::vector<double>& y, const std::vector<double>& x) {
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sxy += x[i] * y[i], sxx += x[i] * x[i];
  return sxy / sxx;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{{"count", "40"}, {"seed", "3"}, {"threads", "1"},
                                          {"course", "flat"}, {"seconds", "5"}, {"legs", "rigid"},
                                          {"dt", "0.005"}, {"collision", "bullet"}, {"ref_dt", "0.005"}};
  if (!bench::read_key_values(argc, argv, "rhex_turning", args)) return 2;
  try {
    const Index count = std::stoll(args["count"]);
    Rng rng(std::stoull(args["seed"]));
    RowMatrix g(count, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    const auto course = enum_from_string(rhex::kObstacleCourseNames, "course", args["course"]);
    const auto legs = enum_from_string(rhex::kLegModelNames, "legs", args["legs"]);
    auto evaluator = make_evaluator(std::stoi(args["threads"]));
    std::vector<std::vector<double>> yaws;
    // DART at ref_dt with Bullet (the reference), then DART at dt with `collision`, then MuJoCo at dt.
    const auto collision = enum_from_string(rhex::kCollisionKindNames, "collision", args["collision"]);
    const std::vector<std::pair<rhex::Engine, double>> runs{
        {rhex::Engine::kDart, std::stod(args["ref_dt"])}, {rhex::Engine::kDart, std::stod(args["dt"])},
        {rhex::Engine::kMujoco, std::stod(args["dt"])}};
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto [engine, dt] = runs[k];
      RhexParams p;
      p.episode.engine = engine;
      bench::set_time_step(p.episode, dt);  // the same 5 s of settling at most, 0.15 s quiet
      if (k == 1) p.episode.collision = collision;
      p.episode.legs = legs;
      p.episode.duration = std::stod(args["seconds"]);
      const RhexTask task(p);
      std::vector<double> yaw(static_cast<std::size_t>(count)), y(yaw.size()), contacts(yaw.size()), dist(yaw.size());
      std::vector<int> dead(yaw.size());
      evaluator->parallel_for(count, [&](Index i) {
        const rhex::EpisodeResult r = task.episode(g.row(i).data(), rhex::RhexEnvironment::obstacle(course));
        const auto j = static_cast<std::size_t>(i);
        yaw[j] = r.final_pose.yaw;
        y[j] = r.final_pose.y;
        dist[j] = r.dead ? 0.0 : r.fitness;
        dead[j] = r.dead;
        contacts[j] = static_cast<double>(r.contacts) / std::max(1, r.walk_steps);
      });
      double ay = 0, ayaw = 0, c = 0, d = 0;
      int nd = 0;
      for (std::size_t j = 0; j < yaw.size(); ++j) {
        ay += std::abs(y[j]) / count, ayaw += std::abs(yaw[j]) / count, c += contacts[j] / count, d += dist[j] / count;
        nd += dead[j];
      }
      fmt::print("{:6s} dt {:.4f}{}: mean {:.3f} m, dead {}, |yaw| {:.3f} rad, |y| {:.3f} m, contacts/step {:.2f}",
                 engine == rhex::Engine::kDart ? "DART" : "MuJoCo", dt, k == 1 ? " " + args["collision"] : "", d, nd, ayaw, ay, c);
      if (!yaws.empty())
        fmt::print("; signed yaw vs DART: r {:.3f}, slope {:.2f}", bench::correlation(yaw, yaws[0]), slope(yaw, yaws[0]));
      fmt::print("\n");
      yaws.push_back(yaw);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_turning: {}\n", e.what());
    return 2;
  }
  return 0;
}
