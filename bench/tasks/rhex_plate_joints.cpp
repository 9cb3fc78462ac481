// How the compliant legs' plate joints actually move in DART, and why a blocked hip walks so
// differently with rigid and compliant legs (docs/fidelity.md, RHex hexapod: "Rigid legs by
// default", "Why the blocked hip differs"). Every actuated hip is driven round at 1 rev/s
// (P gain 15, torque clamped to +-4 N m, as the servo) for 5 s; leg 1 is intact or blocked. For
// each leg model, plate-limit setting and physics step, the program prints the body's forward
// distance and heading, and the plate joints' range of angles over the run (the springs' static
// deflection under the robot's weight is ~1e-5 rad). The physics step is varied here only to see
// what converges; the task's step stays the 5 ms control period. A plain program.
//   rhex_plate_joints [steps=0.005,0.002,0.001,0.0005]
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace {

using namespace qdmeta::rhex;

struct Outcome {
  double forward = 0.0, heading = 0.0;     // m; rad, the body's yaw at the end
  std::array<double, kPlates> low{}, high{};  // per plate joint 1..7, over every leg and step
};

Outcome spin_hips(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  RhexWorld w = build_world(settings, environment);
  Outcome out;
  const int steps = settings.steps();  // the default 5 s episode
  for (int step = 0; step < steps; ++step) {
    const double target = 2.0 * std::numbers::pi * step * settings.time_step;
    for (int i = 0; i < kLegs; ++i)
      if (w.actuated[i]) w.hips[i]->setCommand(0, std::clamp(15.0 * (target - w.hips[i]->getPosition(0)), -4.0, 4.0));
    w.world->step(false);
    for (std::size_t j = 0; j < w.robot->getNumJoints(); ++j) {
      const dart::dynamics::Joint* joint = w.robot->getJoint(j);
      if (joint->getName().rfind("plate_", 0) != 0) continue;
      const auto k = static_cast<std::size_t>(joint->getName().back() - '0');  // plate_<leg>_<k>
      out.low[k] = std::min(out.low[k], joint->getPosition(0));
      out.high[k] = std::max(out.high[k], joint->getPosition(0));
    }
  }
  const Eigen::Isometry3d end = w.body->getWorldTransform();
  out.forward = end.translation().x();
  out.heading = std::atan2(end.linear()(1, 0), end.linear()(0, 0));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> physics_steps{0.005, 0.002, 0.001, 0.0005};
  if (argc > 1) {
    const std::string a = argv[1];
    if (a.rfind("steps=", 0) != 0) {
      fmt::print(stderr, "rhex_plate_joints: bad argument '{}' (steps=a,b,...)\n", a);
      return 2;
    }
    physics_steps.clear();
    std::stringstream list(a.substr(6));
    for (std::string item; std::getline(list, item, ',');) physics_steps.push_back(std::stod(item));
  }
  struct Model {
    const char* name;
    LegModel legs;
    bool limits;
  };
  const std::array<Model, 3> models{{{"rigid", LegModel::kRigid, true},
                                     {"compliant", LegModel::kCompliant, true},
                                     {"compliant, free plate limits", LegModel::kCompliant, false}}};
  fmt::print("hips spun at 1 rev/s for 5 s; distance and heading of the body; plate joint angle ranges (rad)\n");
  for (const double dt : physics_steps) {
    for (const bool blocked : {false, true}) {
      const RhexEnvironment environment =
          blocked ? RhexEnvironment::damaged(DamageType::kBlockedHip, 1) : RhexEnvironment{};
      for (const Model& m : models) {
        EpisodeSettings s;
        s.time_step = dt;
        s.legs = m.legs;
        s.plate_joint_limits = m.limits;
        const Outcome o = spin_hips(s, environment);
        fmt::print("step {:6.4f} s, {:7s}, {:28s}: forward {:6.3f} m, heading {:6.3f} rad", dt,
                   blocked ? "blocked" : "intact", m.name, o.forward, o.heading);
        if (m.legs == LegModel::kCompliant) {
          double widest = 0.0;
          for (int k = 1; k < kPlates; ++k) widest = std::max({widest, -o.low[k], o.high[k]});
          fmt::print("; joints 1..7 range [{:.4f}, {:.4f}] .. [{:.4f}, {:.4f}], largest |angle| {:.4f}", o.low[1],
                     o.high[1], o.low[kPlates - 1], o.high[kPlates - 1], widest);
        }
        fmt::print("\n");
      }
    }
  }
  return 0;
}
