#pragma once
// Builds the DART world of one episode: the RHex robot (with its damage, if any) and the floor
// or obstacle course. Internal to the rhex library: only .cpp files include it.
#include <dart/dynamics/SmartPointer.hpp>
#include <dart/simulation/SmartPointer.hpp>

#include <array>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"
#include "qdmeta/tasks/rhex/rhex_geometry.hpp"  // the robot's facts, shared with tests and the gait export

namespace dart::dynamics {
class BodyNode;
class Joint;
}  // namespace dart::dynamics

namespace qdmeta::rhex {

struct RhexWorld {
  dart::simulation::WorldPtr world;
  dart::dynamics::SkeletonPtr robot;
  dart::dynamics::BodyNode* body = nullptr;
  std::array<dart::dynamics::Joint*, kLegs> hips{};   // nullptr when the leg is removed
  std::array<bool, kLegs> actuated{};                  // false: removed, blocked or passive
  std::array<const dart::dynamics::BodyNode*, kLegs> leg_roots{};  // body driven by each hip
  std::vector<const dart::dynamics::BodyNode*> leg_body_nodes;  // bodies of the legs ...
  std::vector<int> leg_of_body;                                 // ... and whose leg each is
  std::array<int, kLegs> leg_bodies{};
  std::array<int, kLegs> leg_plates{};
  int leg_of(const dart::dynamics::BodyNode* node) const;  // -1 when not a leg
};

RhexWorld build_world(const EpisodeSettings& settings, const RhexEnvironment& environment);

}  // namespace qdmeta::rhex

namespace qdmeta::rhex::detail {
// The robot skeleton, its hips and leg bookkeeping, written into `out`.
void build_robot(const EpisodeSettings& settings, const RhexEnvironment& environment, RhexWorld& out);
// The floor and obstacles of a course: one immobile skeleton.
dart::dynamics::SkeletonPtr build_terrain(ObstacleCourse course);
}  // namespace qdmeta::rhex::detail
