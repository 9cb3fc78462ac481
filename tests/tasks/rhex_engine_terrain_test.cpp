// The obstacle courses as each engine builds them (docs/fidelity.md, "RHex on MuJoCo"): DART's
// terrain skeleton (rhex_terrain.cpp) and MuJoCo's compiled model (rhex_mjcf.cpp) hold the same
// shapes, compared by what the robot meets: each shape's extent in x, y and z (its top surface
// height above all), its kind, friction and whether it collides with the robot. Known tops from
// the course descriptions (docs/fidelity.md), not from the code under test, pin the shared list.
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "qdmeta/tasks/rhex/rhex_mjcf.hpp"
#include "qdmeta/tasks/rhex/rhex_world.hpp"

namespace qdmeta::rhex {
namespace {

struct Extent {
  bool sphere = false;
  Eigen::Vector3d lo, hi;  // axis-aligned bounds in the world (m)
  double friction = 0.0;
};

// Bounds of a box of half-sizes `half` placed at `where`; of a sphere of radius half.x().
Extent extent(bool sphere, const Eigen::Vector3d& half, const Eigen::Isometry3d& where, double friction) {
  const Eigen::Vector3d reach = sphere ? half : Eigen::Vector3d(where.linear().cwiseAbs() * half);
  return {sphere, where.translation() - reach, where.translation() + reach, friction};
}

std::vector<Extent> dart_terrain(ObstacleCourse course) {
  std::vector<Extent> out;
  const auto skeleton = detail::build_terrain(course);
  const auto* body = skeleton->getBodyNode(0);
  for (std::size_t i = 0; i < body->getNumShapeNodes(); ++i) {
    const auto* node = body->getShapeNode(i);
    const auto* shape = node->getShape().get();
    const double friction = node->getDynamicsAspect()->getFrictionCoeff();
    if (const auto* box = dynamic_cast<const dart::dynamics::BoxShape*>(shape))
      out.push_back(extent(false, box->getSize() / 2.0, node->getWorldTransform(), friction));
    else
      out.push_back(extent(true, Eigen::Vector3d::Constant(dynamic_cast<const dart::dynamics::SphereShape&>(*shape).getRadius()),
                           node->getWorldTransform(), friction));
  }
  return out;
}

// The world body's geoms of the compiled model, which are the terrain's; `robot_misses` counts
// those that would not collide with a robot geom (contype 1, conaffinity 0).
std::vector<Extent> mujoco_terrain(ObstacleCourse course, int& robot_misses) {
  char error[1000] = "";
  const std::string xml = rhex_mjcf(EpisodeSettings{}, RhexEnvironment::obstacle(course));
  auto vfs = std::make_unique<mjVFS>();  // large (file names): on the heap
  mj_defaultVFS(vfs.get());
  mj_makeEmptyFileVFS(vfs.get(), "t.xml", static_cast<int>(xml.size()));
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[mj_findFileVFS(vfs.get(), "t.xml")]));
  mjModel* m = mj_loadXML("t.xml", vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  EXPECT_NE(m, nullptr) << error;
  std::vector<Extent> out;
  robot_misses = 0;
  for (int g = 0; m != nullptr && g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] != 0) continue;
    robot_misses += (m->geom_conaffinity[g] & 1) == 0;
    const mjtNum* q = m->geom_quat + 4 * g;
    Eigen::Isometry3d where = Eigen::Isometry3d::Identity();
    where.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    where.translation() = Eigen::Vector3d(m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]);
    const mjtNum* s = m->geom_size + 3 * g;
    const bool sphere = m->geom_type[g] == mjGEOM_SPHERE;
    out.push_back(extent(sphere, sphere ? Eigen::Vector3d::Constant(s[0]) : Eigen::Vector3d(s[0], s[1], s[2]), where,
                         m->geom_friction[3 * g]));
  }
  mj_deleteModel(m);
  return out;
}

double highest_top(const std::vector<Extent>& shapes, double x0, double x1) {
  double top = -1e9;
  for (const Extent& e : shapes)
    if (e.lo.x() < x1 && e.hi.x() > x0) top = std::max(top, e.hi.z());
  return top;
}

TEST(RhexEngineTerrain, EveryCourseHasTheSameShapesOnBothEngines) {
  for (const auto& [course, name] : kObstacleCourseNames) {
    int robot_misses = -1;
    const std::vector<Extent> dart = dart_terrain(course);
    const std::vector<Extent> mujoco = mujoco_terrain(course, robot_misses);
    ASSERT_EQ(dart.size(), mujoco.size()) << name;
    EXPECT_EQ(robot_misses, 0) << name;
    for (std::size_t i = 0; i < dart.size(); ++i) {
      EXPECT_EQ(dart[i].sphere, mujoco[i].sphere) << name << " shape " << i;
      EXPECT_LT((dart[i].lo - mujoco[i].lo).cwiseAbs().maxCoeff(), 1e-12) << name << " shape " << i;
      EXPECT_LT((dart[i].hi - mujoco[i].hi).cwiseAbs().maxCoeff(), 1e-12) << name << " shape " << i;
      EXPECT_EQ(dart[i].friction, kFriction) << name << " shape " << i;
      EXPECT_EQ(mujoco[i].friction, kFriction) << name << " shape " << i;
    }
  }
}

TEST(RhexEngineTerrain, ObstacleTopsAreTheCoursesOnBothEngines) {
  const double slope_end = 0.3 + 10.0 * std::cos(18.0 * std::numbers::pi / 180.0);
  const double slope_top = 10.0 * std::sin(18.0 * std::numbers::pi / 180.0);
  struct Case {
    ObstacleCourse course;
    double x0, x1, top;  // the highest surface over x in [x0, x1]
  };
  const Case cases[] = {
      {ObstacleCourse::kFlat, -1.0, 1.0, 0.0},
      {ObstacleCourse::kThickPipe, 0.5, 0.7, 0.15 + 0.05 * std::sqrt(2.0)},  // a 0.10 m bar turned 45 degrees
      {ObstacleCourse::kThinPipe, 0.3, 0.5, 0.15 + 0.03 * std::sqrt(2.0)},
      {ObstacleCourse::kSlope, slope_end - 0.01, slope_end, slope_top},
      {ObstacleCourse::kStairs, 0.45, 0.55, 0.08},                          // first step's top
      {ObstacleCourse::kRubble, -1.0, 3.5, 0.125},                          // stones up to 0.125 m
      {ObstacleCourse::kSphere, 2.5, 2.7, 0.4},                             // a 6 m sphere 5.6 m down
  };
  for (const Case& c : cases) {
    int robot_misses = -1;
    const double top_dart = highest_top(dart_terrain(c.course), c.x0, c.x1);
    const double top_mujoco = highest_top(mujoco_terrain(c.course, robot_misses), c.x0, c.x1);
    const auto name = enum_to_string(kObstacleCourseNames, c.course);
    EXPECT_NEAR(top_dart, top_mujoco, 1e-12) << name;
    if (c.course == ObstacleCourse::kRubble) {  // 275 stones: the largest near the upper bound
      EXPECT_LE(top_dart, c.top) << name;
      EXPECT_GT(top_dart, 0.12) << name;
    } else
      EXPECT_NEAR(top_dart, c.top, 1e-9) << name;
  }
}

}  // namespace
}  // namespace qdmeta::rhex
