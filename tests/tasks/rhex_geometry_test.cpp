// The RHex robot against the authors' model as they ran it (docs/fidelity.md, "The RHex model"):
// masses, the raised body, hip positions, the backward-bulging legs, the start height and the
// compliant legs' springs. Reference numbers are read off the authors' raised.skel (their plate
// centres, relative to the hip), not computed by the code under test.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <gtest/gtest.h>

#include <cmath>

#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace qdmeta::rhex {
namespace {

RhexWorld robot(LegModel legs, RhexEnvironment env = {}) {
  EpisodeSettings s;
  s.legs = legs;
  return build_world(s, env);
}

// World positions of the plates of `leg`, from the hip outward.
std::vector<Eigen::Vector3d> plate_centres(const RhexWorld& w, int leg) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t b = 0; b < w.leg_body_nodes.size(); ++b) {
    if (w.leg_of_body[b] != leg) continue;
    const auto* node = w.leg_body_nodes[b];
    for (std::size_t s = 0; s < node->getNumShapeNodes(); ++s)
      out.push_back(node->getShapeNode(s)->getWorldTransform().translation());
  }
  return out;
}

Eigen::Vector3d hip_position(const RhexWorld& w, int leg) {
  return w.hips[leg]->getChildBodyNode()->getWorldTransform() * w.hips[leg]->getTransformFromChildBodyNode().translation();
}

TEST(RhexGeometry, MassesAndBodyInertiaAreTheAuthors) {
  for (LegModel legs : {LegModel::kRigid, LegModel::kCompliant}) {
    const RhexWorld w = robot(legs);
    EXPECT_NEAR(w.robot->getMass(), 6.36 + 2 * 0.02 + 48 * 0.0125, 1e-9);  // 7.0 kg
    const Eigen::Matrix3d I = w.body->getInertia().getMoment();
    // raised.skel's body inertia plus the two 20 g spacers 0.205 m to the side.
    EXPECT_NEAR(I(0, 0), 0.09999558 + 2 * (1.6e-7 + 0.02 * 0.205 * 0.205), 1e-9);
    EXPECT_NEAR(I(1, 1), 0.18137058 + 2 * 1.6e-7, 1e-9);
    EXPECT_NEAR(I(2, 2), 0.258825 + 2 * (1.6e-7 + 0.02 * 0.205 * 0.205), 1e-9);
  }
}

TEST(RhexGeometry, BodyIsRaisedAboveTheHipsAtTheAuthorsPositions) {
  const RhexWorld w = robot(LegModel::kRigid);
  EXPECT_NEAR(w.body->getWorldTransform().translation().z(), 0.225, 1e-12);
  const double x[6] = {-0.25, 0.0, 0.25, -0.25, 0.0, 0.25};
  const double y[6] = {0.20475, 0.2245, 0.20475, -0.20475, -0.2245, -0.20475};
  for (int leg = 0; leg < kLegs; ++leg) {
    const Eigen::Vector3d hip = hip_position(w, leg);
    EXPECT_NEAR(hip.x(), x[leg], 1e-12) << leg;
    EXPECT_NEAR(hip.y(), y[leg], 1e-12) << leg;
    EXPECT_NEAR(hip.z(), 0.2, 1e-12) << leg;  // 0.025 m below the body's centre
  }
}

TEST(RhexGeometry, LegsBulgeBackwardThroughTheAuthorsPlateCentres) {
  // raised.skel, leg 4 (middle right, hip at x = 0, z = 0 of its skeleton frame): plate centres
  // (x, z) from the hip outward.
  const double skel[8][2] = {{-0.0153, -0.003043},  {-0.04357, -0.014754}, {-0.06521, -0.03639},
                             {-0.07692, -0.064666}, {-0.07692, -0.095263}, {-0.06521, -0.123534},
                             {-0.04357, -0.145172}, {-0.0153, -0.156883}};
  for (LegModel legs : {LegModel::kRigid, LegModel::kCompliant}) {
    const RhexWorld w = robot(legs);
    for (int leg = 0; leg < kLegs; ++leg) {
      const auto plates = plate_centres(w, leg);
      ASSERT_EQ(plates.size(), 8u);
      const Eigen::Vector3d hip = hip_position(w, leg);
      for (int k = 0; k < 8; ++k) {
        EXPECT_NEAR(plates[k].x() - hip.x(), skel[k][0], 2e-4) << "leg " << leg << " plate " << k;
        EXPECT_NEAR(plates[k].z() - hip.z(), skel[k][1], 2e-4) << "leg " << leg << " plate " << k;
        EXPECT_NEAR(plates[k].y(), hip.y(), 1e-12);
      }
      // The feet start about 4 cm above the floor (top at z = 0).
      EXPECT_NEAR(plates[7].z() - kPlateThickness / 2, 0.040, 2e-3);
    }
  }
}

TEST(RhexGeometry, CompliantLegsHaveTheAuthorsSprings) {
  const RhexWorld w = robot(LegModel::kCompliant);
  EXPECT_EQ(w.robot->getNumBodyNodes(), 1u + 6u * 8u);
  for (int leg = 0; leg < kLegs; ++leg) {
    EXPECT_EQ(w.leg_bodies[leg], 8);
    const dart::dynamics::BodyNode* node = w.leg_roots[leg];
    for (int j = 1; j < 8; ++j) {
      node = node->getChildBodyNode(0);
      const auto* joint = node->getParentJoint();
      EXPECT_DOUBLE_EQ(joint->getSpringStiffness(0), j == 1 || j == 7 ? 202672.0 : 152000.0) << j;
      EXPECT_DOUBLE_EQ(joint->getDampingCoefficient(0), 0.1);
      EXPECT_DOUBLE_EQ(joint->getPositionLowerLimit(0), 0.0);
      EXPECT_NEAR(joint->getPositionUpperLimit(0), 3.141592653589793 / 64, 1e-10);
      EXPECT_DOUBLE_EQ(joint->getRestPosition(0), 0.0);
    }
  }
  const RhexWorld rigid = robot(LegModel::kRigid);
  EXPECT_EQ(rigid.robot->getNumBodyNodes(), 1u + 6u);
}

TEST(RhexGeometry, ShortenedLegKeepsFivePlatesAndRemovedLegNone) {
  const RhexWorld cut = robot(LegModel::kCompliant, RhexEnvironment::damaged(DamageType::kLegShortening, 2));
  EXPECT_EQ(plate_centres(cut, 2).size(), 5u);
  EXPECT_EQ(plate_centres(cut, 1).size(), 8u);
  const RhexWorld removed = robot(LegModel::kRigid, RhexEnvironment::damaged(DamageType::kLegRemoval, 4));
  EXPECT_EQ(removed.hips[4], nullptr);
  EXPECT_TRUE(plate_centres(removed, 4).empty());
  EXPECT_NEAR(removed.robot->getMass(), 7.0 - 8 * 0.0125, 1e-9);
}

}  // namespace
}  // namespace qdmeta::rhex
