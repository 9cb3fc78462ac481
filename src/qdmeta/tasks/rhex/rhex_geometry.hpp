#pragma once
// The RHex robot's geometry, engine-independent (Eigen only): the authors' robot model as they ran
// it (docs/fidelity.md, "The RHex model"). Both engines build their robot from these facts: DART
// in rhex_robot.cpp, MuJoCo through the MJCF of rhex_mjcf.cpp. Body frame: x forward, y left, z
// up, origin at the body box's centre. Plate frame: x along the plate's chord, y lateral, z its
// thickness. Internal to the rhex libraries: only .cpp files (and tests) include it.
#include "qdmeta/core/eigen.hpp"  // before any other Eigen header

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "qdmeta/tasks/rhex/buehler_clock.hpp"

namespace qdmeta::rhex {

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
inline constexpr double kHipDamping = 0.1, kPlateJointDamping = 0.1;
inline constexpr double kFriction = 1.0;  // every shape; restitution 0

// Defined here, inline, so that DART's robot (rhex_robot.cpp) computes them as it always did
// (the same bits: moved out of line they round differently where the compiler fuses operations).
inline constexpr double kPlateArc = std::numbers::pi / kPlates;  // each plate spans pi / 8 of the half circle

inline Eigen::Isometry3d rotation_y(double angle) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return t;
}

// Frame of plate k in the hip frame: origin at the plate's start on the arc, x along its chord
// away from the hip. The half circle of diameter D hangs below the hip:
// point(a) = (-r sin a, 0, r cos a - r), bulging backward at hip angle 0 (as the authors' model);
// a positive hip angle swings the foot backward (stance pushes forward). The chord from point(a)
// to point(a + arc) points along (-cos m, 0, -sin m), m = a + arc / 2, which is x rotated by pi - m.
inline Eigen::Isometry3d plate_frame(int k) {
  const double r = kLegDiameter / 2.0;
  const double a = k * kPlateArc;
  Eigen::Isometry3d t = rotation_y(std::numbers::pi - (a + kPlateArc / 2.0));
  t.translation() = Eigen::Vector3d(-r * std::sin(a), 0.0, r * std::cos(a) - r);
  return t;
}

inline double plate_chord() { return kLegDiameter * std::sin(kPlateArc / 2.0); }

// The plate's box in its own frame: centred half a chord along x.
inline Eigen::Isometry3d plate_shape_offset() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(plate_chord() / 2.0, 0.0, 0.0);
  return t;
}

// Where hip `leg`'s axis sits in the body frame.
Eigen::Vector3d hip_position(int leg);
// Spring stiffness of plate joint k (between plates k - 1 and k, k = 1..7), N m / rad.
double plate_joint_stiffness(int k);

// Mass, centre of mass and moment of inertia (about the centre of mass) of a rigid part.
struct MassProperties {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
};
// Plates placed at `frames` (in the part's frame), by the parallel-axis theorem. Each plate's own
// inertia is the authors' (about 6x a uniform box of its size).
MassProperties plates_mass(const std::vector<Eigen::Isometry3d>& frames);
// The body box with its two spacers (shapes of the body, their masses and inertias added).
MassProperties body_mass();
// Centre of spacer `side` (+1 left, -1 right) in the body frame.
Eigen::Vector3d spacer_position(double side);

// XYZ Euler angles of a rotation: DART's matrixToEulerXYZ for either engine (rhex_world.cpp).
Eigen::Vector3d euler_xyz(const Eigen::Matrix3d& r);

}  // namespace qdmeta::rhex
