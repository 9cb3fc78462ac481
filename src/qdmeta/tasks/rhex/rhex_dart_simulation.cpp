// The DART engine behind the episode (rhex_simulation.hpp): the world of rhex_world.cpp.
#include <dart/collision/CollisionObject.hpp>
#include <dart/collision/CollisionResult.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/Joint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/simulation/World.hpp>

#include "qdmeta/tasks/rhex/rhex_simulation.hpp"
#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace qdmeta::rhex {
namespace {

class DartSimulation final : public Simulation {
 public:
  DartSimulation(const EpisodeSettings& settings, const RhexEnvironment& environment)
      : w_(build_world(settings, environment)) {
    actuated = w_.actuated;
    leg_bodies = w_.leg_bodies;
    leg_plates = w_.leg_plates;
  }
  void step() override { w_.world->step(false); }
  Eigen::Isometry3d body_pose() const override { return w_.body->getWorldTransform(); }
  Eigen::Vector3d com_velocity() const override { return w_.robot->getCOMLinearVelocity(); }
  bool has_hip(int leg) const override { return w_.hips[leg] != nullptr && w_.hips[leg]->getNumDofs() == 1; }
  double hip_angle(int leg) const override { return w_.hips[leg]->getPosition(0); }
  void set_hip_torque(int leg, double torque) override { w_.hips[leg]->setCommand(0, torque); }
  Eigen::Matrix3d leg_rotation(int leg) const override { return w_.leg_roots[leg]->getWorldTransform().linear(); }
  std::int64_t contact_count() const override {
    return static_cast<std::int64_t>(w_.world->getLastCollisionResult().getNumContacts());
  }
  std::array<bool, kLegs> legs_touching() const override {
    std::array<bool, kLegs> touching{};
    for (const auto& contact : w_.world->getLastCollisionResult().getContacts()) {
      for (const auto* object : {contact.collisionObject1, contact.collisionObject2}) {
        const auto* shape = dynamic_cast<const dart::dynamics::ShapeNode*>(object->getShapeFrame());
        if (shape == nullptr) continue;
        const int leg = w_.leg_of(shape->getBodyNodePtr().get());
        if (leg >= 0) touching[leg] = true;
      }
    }
    return touching;
  }

 private:
  RhexWorld w_;
};

}  // namespace

std::unique_ptr<Simulation> make_dart_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  return std::make_unique<DartSimulation>(settings, environment);
}

}  // namespace qdmeta::rhex
