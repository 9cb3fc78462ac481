// Where and how RHex robots die on a course, on DART and on MuJoCo (docs/fidelity.md, "Why
// MuJoCo's robots turn over on the slope and the pipes"): the cross-check's random controllers
// (seed 3, the first `count` of its 200), rigid or compliant legs, each episode's body pose
// recorded every step. One line per episode that dies on either engine: per engine the time of
// death, the body's position and heading (yaw) then, and the world direction of its up-axis
// (which way it fell: x forward/backward, y sideways); then per engine the deaths, how many fell
// beyond |y| > `edge` (off a board's side), and the mean |yaw| and |y| at 2 s over all episodes.
// trace=K instead prints controller K's every step on both engines as CSV
// (engine,t,x,y,z,roll,pitch,yaw,up_x,up_y,up_z). Not a micro-benchmark: a plain program.
// fine_dt > 0 adds DART at that step (the converged reference: docs/fidelity.md).
//   rhex_deaths [course=slope] [count=40] [legs=rigid] [edge=0.5] [trace=-1] [fine_dt=0]
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"
#include "tasks/key_value_args.hpp"
#include "tasks/rhex_time_step.hpp"

namespace {

using namespace qdmeta;

constexpr Index kCrosscheckControllers = 200;

// The body's z-axis in the world from DART's XYZ Euler angles (R = Rx(roll) Ry(pitch) Rz(yaw)).
std::array<double, 3> up_axis(const rhex::PoseRecord& p) {
  const double a = p.euler[0], b = p.euler[1];
  return {std::sin(b), -std::sin(a) * std::cos(b), std::cos(a) * std::cos(b)};
}

const rhex::PoseRecord& at(const rhex::EpisodeResult& r, double t, double dt) {
  const auto k = static_cast<std::size_t>(std::lround(t / dt)) - 1;
  return r.poses[std::min(k, r.poses.size() - 1)];
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> args{
      {"course", "slope"}, {"count", "40"}, {"legs", "rigid"}, {"edge", "0.5"}, {"trace", "-1"}, {"fine_dt", "0"}};
  if (!bench::read_key_values(argc, argv, "rhex_deaths", args)) return 2;
  try {
    const Index count = std::min<Index>(kCrosscheckControllers, std::stoll(args["count"]));
    Rng rng(3);
    RowMatrix g(kCrosscheckControllers, rhex::kGenes);
    for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
    const auto env = rhex::RhexEnvironment::obstacle(enum_from_string(rhex::kObstacleCourseNames, "course", args["course"]));
    const double edge = std::stod(args["edge"]);
    const Index trace = std::stoll(args["trace"]);
    // DART and MuJoCo at the authors' 5 ms; DART at `fine_dt` (the converged reference) if asked.
    std::vector<std::pair<std::string, RhexTask>> engines;
    const double fine_dt = std::stod(args["fine_dt"]);
    for (const auto& [engine, dt] : std::vector<std::pair<rhex::Engine, double>>{
             {rhex::Engine::kDart, 0.005}, {rhex::Engine::kMujoco, 0.005}, {rhex::Engine::kDart, fine_dt}}) {
      if (dt <= 0.0) continue;
      RhexParams p;
      p.episode.engine = engine;
      p.episode.legs = enum_from_string(rhex::kLegModelNames, "legs", args["legs"]);
      p.episode.record_poses = true;
      bench::set_time_step(p.episode, dt);
      engines.emplace_back(fmt::format("{}@{:g}ms", enum_to_string(rhex::kEngineNames, engine), 1000 * dt), RhexTask(p));
    }
    if (trace >= 0) {
      fmt::print("engine,t,x,y,z,roll,pitch,yaw,up_x,up_y,up_z\n");
      for (const auto& [name, task] : engines)
        for (const auto& p : task.episode(g.row(trace).data(), env).poses) {
          const auto up = up_axis(p);
          fmt::print("{},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}\n", name, p.time,
                     p.position[0], p.position[1], p.position[2], p.euler[0], p.euler[1], p.euler[2], up[0], up[1], up[2]);
        }
      return 0;
    }
    struct Tally {
      int deaths = 0, beyond_edge = 0;
      double yaw2 = 0.0, y2 = 0.0;
    };
    std::vector<Tally> tally(engines.size());
    fmt::print("controller | per engine: t death (s), x, y, z, yaw, up-axis (x, y, z) at death | - alive\n");
    for (Index i = 0; i < count; ++i) {
      std::vector<rhex::EpisodeResult> runs;
      for (const auto& [name, task] : engines) runs.push_back(task.episode(g.row(i).data(), env));
      std::string line = fmt::format("{:3d}", i);
      bool any = false;
      for (std::size_t e = 0; e < runs.size(); ++e) {
        const auto& r = runs[e];
        const double dt = engines[e].second.params().episode.time_step;
        const auto& two = at(r, 2.0, dt);
        tally[e].yaw2 += std::abs(two.euler[2]) / static_cast<double>(count);
        tally[e].y2 += std::abs(two.position[1]) / static_cast<double>(count);
        if (!r.turned_over) {
          line += fmt::format(" | {:11s} alive {:.2f} m", engines[e].first, r.fitness);
          continue;
        }
        any = true;
        const auto& p = r.poses[static_cast<std::size_t>(r.walk_steps) - 1];
        const auto up = up_axis(p);
        ++tally[e].deaths;
        tally[e].beyond_edge += std::abs(p.position[1]) > edge;
        line += fmt::format(" | {:11s} {:.2f}: {:+.2f} {:+.2f} {:+.2f}, yaw {:+.2f}, up ({:+.2f} {:+.2f} {:+.2f})",
                            engines[e].first, p.time, p.position[0], p.position[1], p.position[2], p.euler[2], up[0],
                            up[1], up[2]);
      }
      if (any) fmt::print("{}\n", line);
    }
    for (std::size_t e = 0; e < engines.size(); ++e)
      fmt::print("{}: {} of {} turned over, {} of them beyond |y| > {}; at 2 s mean |yaw| {:.3f} rad, |y| {:.3f} m\n",
                 engines[e].first, tally[e].deaths, count, tally[e].beyond_edge, edge, tally[e].yaw2, tally[e].y2);
  } catch (const std::exception& e) {
    fmt::print(stderr, "rhex_deaths: {}\n", e.what());
    return 2;
  }
  return 0;
}
