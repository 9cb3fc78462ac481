#include "qdmeta/tasks/rhex/rhex_geometry.hpp"

#include <cmath>
#include <numbers>

namespace qdmeta::rhex {
namespace {

Eigen::Matrix3d diagonal(const std::array<double, 3>& d) { return Eigen::Vector3d(d[0], d[1], d[2]).asDiagonal(); }

}  // namespace

Eigen::Vector3d hip_position(int leg) { return {kHipX[leg], kHipY[leg], -kBodyAboveHips}; }

double plate_joint_stiffness(int k) { return k == 1 || k == kPlates - 1 ? kStiffnessAtEnds : kStiffnessBetween; }

MassProperties plates_mass(const std::vector<Eigen::Isometry3d>& frames) {
  const Eigen::Matrix3d own = diagonal(kPlateInertia);
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  for (const auto& f : frames) com += f.translation();
  com /= static_cast<double>(frames.size());
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (const auto& f : frames) {
    const Eigen::Vector3d c = f.translation() - com;
    moment += f.linear() * own * f.linear().transpose() +
              kPlateMass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  return {kPlateMass * static_cast<double>(frames.size()), com, moment};
}

Eigen::Vector3d spacer_position(double side) { return {0.0, side * kSpacerY, 0.0}; }

MassProperties body_mass() {
  Eigen::Matrix3d moment = diagonal(kBodyInertia);
  for (const double side : {1.0, -1.0}) {
    const Eigen::Vector3d c = spacer_position(side);
    moment += kSpacerInertia * Eigen::Matrix3d::Identity() +
              kSpacerMass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  return {kBodyMass + 2.0 * kSpacerMass, Eigen::Vector3d::Zero(), moment};
}

}  // namespace qdmeta::rhex
