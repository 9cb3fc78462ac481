#include "qdmeta/tasks/rhex/rhex_world.hpp"

#include <dart/collision/bullet/BulletCollisionDetector.hpp>
#include <dart/collision/dart/DARTCollisionDetector.hpp>
#include <dart/collision/fcl/FCLCollisionDetector.hpp>
#include <dart/constraint/BoxedLcpConstraintSolver.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/constraint/PgsBoxedLcpSolver.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/math/Geometry.hpp>
#include <dart/simulation/World.hpp>

#include <algorithm>

namespace qdmeta::rhex {
namespace {

std::shared_ptr<dart::collision::CollisionDetector> make_detector(CollisionKind kind) {
  switch (kind) {
    case CollisionKind::kBullet: return dart::collision::BulletCollisionDetector::create();
    case CollisionKind::kDart: return dart::collision::DARTCollisionDetector::create();
    case CollisionKind::kFcl: return dart::collision::FCLCollisionDetector::create();
  }
  return dart::collision::BulletCollisionDetector::create();
}

}  // namespace

Eigen::Vector3d euler_xyz(const Eigen::Matrix3d& r) { return dart::math::matrixToEulerXYZ(r); }

int RhexWorld::leg_of(const dart::dynamics::BodyNode* node) const {
  const auto it = std::find(leg_body_nodes.begin(), leg_body_nodes.end(), node);
  return it == leg_body_nodes.end() ? -1 : leg_of_body[static_cast<std::size_t>(it - leg_body_nodes.begin())];
}

RhexWorld build_world(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  RhexWorld out;
  out.world = dart::simulation::World::create("rhex");
  out.world->setTimeStep(settings.time_step);
  out.world->setGravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  out.world->getConstraintSolver()->setCollisionDetector(make_detector(settings.collision));
  if (settings.lcp == LcpSolver::kPgs) {
    auto* solver = dynamic_cast<dart::constraint::BoxedLcpConstraintSolver*>(out.world->getConstraintSolver());
    if (solver != nullptr) solver->setBoxedLcpSolver(std::make_shared<dart::constraint::PgsBoxedLcpSolver>());
  }
  detail::build_robot(settings, environment, out);
  out.world->addSkeleton(out.robot);
  out.world->addSkeleton(detail::build_terrain(environment.course));
  return out;
}

}  // namespace qdmeta::rhex
