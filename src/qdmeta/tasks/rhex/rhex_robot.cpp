// The RHex robot built programmatically from the facts of the authors' model (docs/fidelity.md, "The
// RHex model"): a box body with two side spacers on a free joint, raised above six revolute hips
// about the lateral (y) axis, each driving a half-circle leg of 8 plates that bulges backward.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/WeldJoint.hpp>

#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace qdmeta::rhex::detail {
namespace {

using dart::dynamics::BodyNode;
using dart::dynamics::BoxShape;
using dart::dynamics::CollisionAspect;
using dart::dynamics::DynamicsAspect;
using dart::dynamics::VisualAspect;

void add_box_shape(BodyNode* node, const Eigen::Vector3d& size, const Eigen::Isometry3d& where) {
  auto box = std::make_shared<BoxShape>(size);
  auto* shape = node->createShapeNodeWith<VisualAspect, CollisionAspect, DynamicsAspect>(box);
  shape->setRelativeTransform(where);
  shape->getDynamicsAspect()->setFrictionCoeff(kFriction);
  shape->getDynamicsAspect()->setRestitutionCoeff(0.0);
}

void add_plate_shape(BodyNode* node, const Eigen::Isometry3d& where) {
  add_box_shape(node, Eigen::Vector3d(kPlateLength, kPlateWidth, kPlateThickness), where);
}

dart::dynamics::Inertia inertia(const MassProperties& m) { return {m.mass, m.com, m.moment}; }

// Joint from the robot body to the leg's first body, at the hip; `plate0` places that body's
// frame in the hip frame.
template <class JointType>
typename JointType::Properties hip_properties(int leg, const Eigen::Isometry3d& plate0) {
  typename JointType::Properties props;
  props.mName = "hip_" + std::to_string(leg);
  props.mT_ParentBodyToJoint.translation() = hip_position(leg);
  props.mT_ChildBodyToJoint = plate0.inverse();
  return props;
}

void build_leg(int leg, DamageType damage, const EpisodeSettings& settings, BodyNode* body, RhexWorld& out) {
  const LegModel model = settings.legs;
  const int plates = damage == DamageType::kLegShortening ? kShortenedPlates : kPlates;
  dart::dynamics::BodyNode::Properties leg_props;
  leg_props.mName = "leg_" + std::to_string(leg);

  // The body that the hip drives: the whole rigid leg, or its first plate.
  const Eigen::Isometry3d first_frame = model == LegModel::kRigid ? Eigen::Isometry3d::Identity() : plate_frame(0);
  BodyNode* root = nullptr;
  dart::dynamics::Joint* hip = nullptr;
  if (damage == DamageType::kBlockedHip) {
    auto [joint, node] = out.robot->createJointAndBodyNodePair<dart::dynamics::WeldJoint>(
        body, hip_properties<dart::dynamics::WeldJoint>(leg, first_frame), leg_props);
    hip = joint;
    root = node;
  } else {
    auto props = hip_properties<dart::dynamics::RevoluteJoint>(leg, first_frame);
    props.mAxis = Eigen::Vector3d::UnitY();
    props.mDampingCoefficients[0] = kHipDamping;
    props.mActuatorType = damage == DamageType::kPassiveHip ? dart::dynamics::Joint::PASSIVE : dart::dynamics::Joint::FORCE;
    auto [joint, node] = out.robot->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(body, props, leg_props);
    hip = joint;
    root = node;
  }
  out.hips[leg] = hip;
  out.leg_roots[leg] = root;
  out.actuated[leg] = damage == DamageType::kNone || damage == DamageType::kLegShortening;
  out.leg_plates[leg] = plates;

  if (model == LegModel::kRigid) {
    std::vector<Eigen::Isometry3d> frames;
    for (int k = 0; k < plates; ++k) {
      frames.push_back(plate_frame(k) * plate_shape_offset());
      add_plate_shape(root, frames.back());
    }
    root->setInertia(inertia(plates_mass(frames)));
    out.leg_body_nodes.push_back(root);
    out.leg_of_body.push_back(leg);
    out.leg_bodies[leg] = 1;
    return;
  }
  // Compliant: plate k's frame sits at its start on the arc; joint k-1 -> k is a stiff spring.
  BodyNode* parent = root;
  for (int k = 0; k < plates; ++k) {
    BodyNode* node = parent;
    if (k > 0) {
      dart::dynamics::RevoluteJoint::Properties props;
      props.mName = "plate_" + std::to_string(leg) + "_" + std::to_string(k);
      props.mAxis = Eigen::Vector3d::UnitY();
      props.mT_ParentBodyToJoint = plate_frame(k - 1).inverse() * plate_frame(k);
      props.mSpringStiffnesses[0] = plate_joint_stiffness(k);
      props.mRestPositions[0] = 0.0;
      props.mDampingCoefficients[0] = kPlateJointDamping;
      props.mPositionLowerLimits[0] = 0.0;
      props.mPositionUpperLimits[0] = kPlateJointUpper;
      props.mIsPositionLimitEnforced = settings.plate_joint_limits;
      props.mActuatorType = dart::dynamics::Joint::PASSIVE;
      dart::dynamics::BodyNode::Properties plate_props;
      plate_props.mName = "leg_" + std::to_string(leg) + "_plate_" + std::to_string(k);
      node = out.robot->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(parent, props, plate_props).second;
    }
    add_plate_shape(node, plate_shape_offset());
    node->setInertia(inertia(plates_mass({plate_shape_offset()})));
    out.leg_body_nodes.push_back(node);
    out.leg_of_body.push_back(leg);
    ++out.leg_bodies[leg];
    parent = node;
  }
}

}  // namespace

void build_robot(const EpisodeSettings& settings, const RhexEnvironment& environment, RhexWorld& out) {
  out.robot = dart::dynamics::Skeleton::create("rhex");
  dart::dynamics::FreeJoint::Properties free_props;
  free_props.mName = "free";
  dart::dynamics::BodyNode::Properties body_props;
  body_props.mName = "body";
  BodyNode* body = out.robot->createJointAndBodyNodePair<dart::dynamics::FreeJoint>(nullptr, free_props, body_props).second;
  add_box_shape(body, Eigen::Vector3d(kBodyLength, kBodyWidth, kBodyHeight), Eigen::Isometry3d::Identity());
  // The spacers are welded to the body in the authors' model: here they are shapes of the body,
  // their masses and inertias added to its own (the same dynamics, two bodies fewer).
  for (const double side : {1.0, -1.0}) {
    Eigen::Isometry3d where = Eigen::Isometry3d::Identity();
    where.translation() = spacer_position(side);
    add_box_shape(body, Eigen::Vector3d(kSpacerLength, kSpacerWidth, kBodyHeight), where);
  }
  body->setInertia(inertia(body_mass()));
  out.body = body;

  for (int leg = 0; leg < kLegs; ++leg) {
    const DamageType damage = environment.leg == leg ? environment.damage : DamageType::kNone;
    if (damage == DamageType::kLegRemoval) {
      out.hips[leg] = nullptr;
      out.actuated[leg] = false;
      continue;
    }
    build_leg(leg, damage, settings, body, out);
  }

  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.translation() = Eigen::Vector3d(0.0, 0.0, kStartHeight);
  dart::dynamics::FreeJoint::setTransformOf(body, start);
}

}  // namespace qdmeta::rhex::detail
