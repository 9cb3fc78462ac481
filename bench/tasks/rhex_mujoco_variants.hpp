#pragma once
// MuJoCo's option variants that the settings sweep (rhex_mujoco_settings) and the tripod benchmark
// (rhex_bench, BM_RhexMujocoVariant) measure against the faithful setting: the step, the solver
// with its iterations and tolerance, the friction cone, the integrator and the no-slip pass.
// MuJoCo 2.2.2 has no ls_iterations (its line search is fixed) and no implicitfast; its
// "implicit" also treats the compliant legs' damping actuators implicitly, which the faithful
// model writes explicitly (rhex_mjcf.cpp): that variant changes the compliant model, not only
// its numerics.
#include <string>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"
#include "tasks/rhex_time_step.hpp"

namespace qdmeta::bench {

struct MujocoVariant {
  std::string name;
  double time_step = 0.005;
  rhex::MujocoOptions options;
};

inline std::vector<MujocoVariant> rhex_mujoco_variants() {
  using Solver = rhex::MujocoOptions::Solver;
  auto with = [](std::string name, double dt, auto change) {
    MujocoVariant v{std::move(name), dt, {}};
    change(v.options);
    return v;
  };
  auto same = [](rhex::MujocoOptions&) {};
  return {
      with("faithful", 0.005, same),
      with("step-10ms", 0.010, same),
      with("newton-tol-1e-5", 0.005, [](auto& o) { o.tolerance = 1e-5; }),
      with("newton-iter-3", 0.005, [](auto& o) { o.iterations = 3; }),
      with("cg", 0.005, [](auto& o) { o.solver = Solver::kCg; }),
      with("cg-iter-20-tol-1e-5", 0.005, [](auto& o) { o.solver = Solver::kCg, o.iterations = 20, o.tolerance = 1e-5; }),
      with("pgs", 0.005, [](auto& o) { o.solver = Solver::kPgs; }),
      with("pgs-iter-20", 0.005, [](auto& o) { o.solver = Solver::kPgs, o.iterations = 20; }),
      with("elliptic", 0.005, [](auto& o) { o.elliptic_cone = true; }),
      with("implicit", 0.005, [](auto& o) { o.implicit = true; }),
      with("noslip-10", 0.005, [](auto& o) { o.noslip_iterations = 10; }),
  };
}

// `settings` under variant `v`.
inline void apply(const MujocoVariant& v, rhex::EpisodeSettings& settings) {
  settings.engine = rhex::Engine::kMujoco;
  set_time_step(settings, v.time_step);
  settings.mujoco = v.options;
}

}  // namespace qdmeta::bench
