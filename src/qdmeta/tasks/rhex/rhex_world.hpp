#pragma once
// Builds the DART world of one episode: the RHex robot (with its damage, if any) and the floor
// or obstacle course. Internal to the rhex library: only .cpp files include it.
#include <dart/dynamics/SmartPointer.hpp>
#include <dart/simulation/SmartPointer.hpp>

#include <array>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"

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

// Geometry shared with tests and the gait export: the authors' robot model as they ran it
// (docs/fidelity.md, "The RHex model"). Body frame: x forward, y left, z up, origin at the
// body box's centre. Plate frame: x along the plate's chord, y lateral, z its thickness.
inline constexpr double kBodyLength = 0.54, kBodyWidth = 0.39, kBodyHeight = 0.139, kBodyMass = 6.36;
inline constexpr std::array<double, 3> kBodyInertia{0.09999558, 0.18137058, 0.258825};  // about x, y, z
inline constexpr double kBodyAboveHips = 0.025;  // the "raised" body: its centre above the hip axes
inline constexpr double kStartHeight = 0.225;    // body centre at the start (hips 0.2 m up, feet ~4 cm)
// Two spacers welded to the body's sides carry the middle legs.
inline constexpr double kSpacerLength = 0.05, kSpacerWidth = 0.02, kSpacerMass = 0.02, kSpacerY = 0.205;
inline constexpr double kSpacerInertia = 1.6e-7;  // about each axis
inline constexpr double kLegDiameter = 0.160;     // circle through the plates' joints
inline constexpr int kPlates = 8, kShortenedPlates = 5;
inline constexpr double kPlateLength = 0.0312, kPlateWidth = 0.0175, kPlateThickness = 0.003, kPlateMass = 0.0125;
inline constexpr std::array<double, 3> kPlateInertia{5.2e-7, 7.33e-6, 7.84e-6};  // about the plate's x, y, z
inline constexpr std::array<double, kLegs> kHipX{-0.25, 0.0, 0.25, -0.25, 0.0, 0.25};
inline constexpr std::array<double, kLegs> kHipY{0.20475, 0.2245, 0.20475, -0.20475, -0.2245, -0.20475};
// Plate joint j (between plates j and j + 1, j = 1..7): stiffer at the two ends of the leg.
inline constexpr double kStiffnessAtEnds = 202672.0, kStiffnessBetween = 152000.0;
inline constexpr double kPlateJointUpper = 0.04908738521;  // pi / 64: how far a joint may open

}  // namespace qdmeta::rhex

namespace qdmeta::rhex::detail {
// The robot skeleton, its hips and leg bookkeeping, written into `out`.
void build_robot(const EpisodeSettings& settings, const RhexEnvironment& environment, RhexWorld& out);
// The floor and obstacles of a course: one immobile skeleton.
dart::dynamics::SkeletonPtr build_terrain(ObstacleCourse course);
}  // namespace qdmeta::rhex::detail
