#pragma once
// What an episode needs from a physics engine (rhex_episode.cpp), engine-independent: the world of
// one environment, built fresh, stepped one control cycle at a time, with the robot's body pose,
// its hips and legs, and the contacts of the last step. DART (rhex_dart_simulation.cpp) and
// MuJoCo (rhex_mujoco_simulation.cpp, library qdmeta_rhex_mujoco) implement it. Internal to the
// rhex libraries.
#include "qdmeta/core/eigen.hpp"  // before any other Eigen header

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <memory>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"

namespace qdmeta::rhex {

class Simulation {
 public:
  virtual ~Simulation() = default;
  // Advances one time step under the hip torques set since the last step.
  virtual void step() = 0;
  virtual Eigen::Isometry3d body_pose() const = 0;    // the body box's frame in the world
  virtual Eigen::Vector3d com_velocity() const = 0;   // of the whole robot (m/s)
  virtual bool has_hip(int leg) const = 0;            // a revolute hip (not removed, not blocked)
  virtual double hip_angle(int leg) const = 0;        // rad, only where has_hip
  virtual void set_hip_torque(int leg, double torque) = 0;  // only where actuated
  // World rotation of the body that hip `leg` drives (the rigid leg, or its first plate), as
  // DART's frame of that body; only where leg_bodies[leg] > 0.
  virtual Eigen::Matrix3d leg_rotation(int leg) const = 0;
  virtual std::int64_t contact_count() const = 0;     // contact points of the last step
  virtual std::array<bool, kLegs> legs_touching() const = 0;  // any plate of each leg in contact
  // The engine gave up on the state (MuJoCo: a non-finite or huge acceleration, after which it
  // resets the state): the episode is dead.
  virtual bool diverged() const { return false; }

  std::array<bool, kLegs> actuated{};  // false: removed, blocked or passive
  std::array<int, kLegs> leg_bodies{};  // rigid bodies of each leg (0 when removed)
  std::array<int, kLegs> leg_plates{};  // collision plates of each leg
};

// A fresh world of `environment` in settings.engine.
std::unique_ptr<Simulation> make_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment);

// The engines behind make_simulation.
std::unique_ptr<Simulation> make_dart_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment);
std::unique_ptr<Simulation> make_mujoco_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment);

}  // namespace qdmeta::rhex
