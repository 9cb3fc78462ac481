// The DART terrain of a course: its shapes (rhex_course.cpp) on one immobile skeleton.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/WeldJoint.hpp>

#include "qdmeta/tasks/rhex/rhex_course.hpp"
#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace qdmeta::rhex::detail {

dart::dynamics::SkeletonPtr build_terrain(ObstacleCourse course) {
  auto skeleton = dart::dynamics::Skeleton::create("terrain");
  dart::dynamics::WeldJoint::Properties joint;
  joint.mName = "ground";
  auto* body = skeleton->createJointAndBodyNodePair<dart::dynamics::WeldJoint>(nullptr, joint).second;
  skeleton->setMobile(false);
  for (const TerrainShape& s : course_shapes(course)) {
    dart::dynamics::ShapePtr shape;
    if (s.kind == TerrainShape::Kind::kBox) shape = std::make_shared<dart::dynamics::BoxShape>(s.size);
    else shape = std::make_shared<dart::dynamics::SphereShape>(s.radius);
    auto* node = body->createShapeNodeWith<dart::dynamics::VisualAspect, dart::dynamics::CollisionAspect,
                                           dart::dynamics::DynamicsAspect>(shape);
    node->setRelativeTransform(s.where);
    node->getDynamicsAspect()->setFrictionCoeff(kFriction);
    node->getDynamicsAspect()->setRestitutionCoeff(0.0);
  }
  return skeleton;
}

}  // namespace qdmeta::rhex::detail
