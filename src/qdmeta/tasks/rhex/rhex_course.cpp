// Floors and obstacle courses (docs/specification.md, RHex) as lists of fixed shapes. Floors are 0.2 m
// thick boxes with their top at z = 0; x is forward, the robot starts over the origin. Where
// docs/specification.md leaves a dimension open, the choice is documented in docs/fidelity.md.
#include "qdmeta/tasks/rhex/rhex_course.hpp"

#include <cmath>
#include <numbers>

#include "qdmeta/core/rng.hpp"

namespace qdmeta::rhex {
namespace {

using std::numbers::pi;

constexpr double kFloorThickness = 0.2;
constexpr std::uint64_t kRubbleSeed = 0x5275626275ULL;  // fixed: the rubble is part of the course

double degrees(double d) { return d * pi / 180.0; }

class TerrainBuilder {
 public:
  std::vector<TerrainShape> done() { return std::move(shapes_); }

  // A box of `size`, centred at `centre`, rotated by `pitch` about y.
  void box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre, double pitch = 0.0) {
    Eigen::Isometry3d where = Eigen::Isometry3d::Identity();
    where.linear() = Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
    where.translation() = centre;
    shapes_.push_back({TerrainShape::Kind::kBox, size, 0.0, where});
  }
  void sphere(double radius, const Eigen::Vector3d& centre) {
    Eigen::Isometry3d where = Eigen::Isometry3d::Identity();
    where.translation() = centre;
    shapes_.push_back({TerrainShape::Kind::kSphere, Eigen::Vector3d::Zero(), radius, where});
  }
  // A floor of length x width with its top at `top`, spanning x in [x0, x0 + length].
  void floor(double x0, double length, double width, double top = 0.0) {
    box({length, width, kFloorThickness}, {x0 + length / 2.0, 0.0, top - kFloorThickness / 2.0});
  }
  // A centred floor (the robot starts over its middle).
  void centred_floor(double length, double width) { floor(-length / 2.0, length, width); }
  // A board whose top surface starts at (x0, 0, z0) and runs `length` along x tilted by `angle`
  // (positive: rising).
  void board(double x0, double z0, double length, double width, double angle) {
    const Eigen::Vector3d along(std::cos(angle), 0.0, std::sin(angle));
    const Eigen::Vector3d up(-std::sin(angle), 0.0, std::cos(angle));
    const Eigen::Vector3d centre = Eigen::Vector3d(x0, 0.0, z0) + along * (length / 2.0) - up * (kFloorThickness / 2.0);
    box({length, width, kFloorThickness}, centre, -angle);
  }

 private:
  std::vector<TerrainShape> shapes_;
};

void sphere_course(TerrainBuilder& t) {
  t.centred_floor(20.0, 2.0);
  t.sphere(6.0, {2.6, 0.0, -5.6});
}

void stairs(TerrainBuilder& t) {
  t.centred_floor(20.0, 5.0);
  for (int i = 0; i < 100; ++i) t.box({0.2, 5.0, 0.08}, {0.4 + 0.2 * i, 0.0, 0.08 * i - 0.04});
}

void slope(TerrainBuilder& t) {
  t.centred_floor(1.0, 1.0);
  t.board(0.3, 0.0, 10.0, 1.0, degrees(18.0));
}

void rubble(TerrainBuilder& t) {
  t.centred_floor(20.0, 2.0);
  Rng rng(kRubbleSeed);
  for (int i = 0; i < 275; ++i) {
    const double x = rng.uniform(0.0, 3.0);
    const double y = rng.uniform(-1.0, 1.0);
    const double radius = rng.uniform(0.025, 0.125);
    t.sphere(radius, {x, y, 0.0});
  }
}

// Ten steps of 0.18 m between x = 0.5 and 2.3, tops 0, -0.05, ..., -0.20, -0.25, -0.20, ..., -0.05,
// then a platform at 0.
void down_up_stairs(TerrainBuilder& t) {
  t.centred_floor(1.0, 5.0);
  constexpr double kTops[10] = {0.0, -0.05, -0.10, -0.15, -0.20, -0.25, -0.20, -0.15, -0.10, -0.05};
  for (int i = 0; i < 10; ++i) t.floor(0.5 + 0.18 * i, 0.18, 5.0, kTops[i]);
  t.floor(2.3, 5.0, 5.0, 0.0);
}

void many_pipes(TerrainBuilder& t) {
  t.centred_floor(20.0, 10.0);
  for (int i = 0; i < 10; ++i) t.box({0.03, 10.0, 0.03}, {0.4 + 1.0 * i, 0.0, 0.015}, degrees(45.0));
}

// Start piece (x in [-0.3, 0.3]), 15-degree ramp 0.65 m down, 0.6 m flat bottom, ramp up, then a
// 5 x 5 platform at the start height.
void ditch(TerrainBuilder& t) {
  const double angle = degrees(15.0), ramp = 0.65;
  const double run = ramp * std::cos(angle), depth = ramp * std::sin(angle);
  t.floor(-0.3, 0.6, 5.0, 0.0);
  t.board(0.3, 0.0, ramp, 5.0, -angle);
  t.floor(0.3 + run, 0.6, 5.0, -depth);
  t.board(0.9 + run, -depth, ramp, 5.0, angle);
  t.floor(0.9 + 2.0 * run, 5.0, 5.0, 0.0);
}

// Two square bars, one turned 45 degrees about y: an octagonal pipe across the path.
void pipe(TerrainBuilder& t, double side, double x) {
  t.centred_floor(20.0, 10.0);
  t.box({side, 10.0, side}, {x, 0.0, 0.15});
  t.box({side, 10.0, side}, {x, 0.0, 0.15}, degrees(45.0));
}

}  // namespace

std::vector<TerrainShape> course_shapes(ObstacleCourse course) {
  TerrainBuilder t;
  switch (course) {
    case ObstacleCourse::kFlat: t.centred_floor(100.0, 100.0); break;
    case ObstacleCourse::kSphere: sphere_course(t); break;
    case ObstacleCourse::kStairs: stairs(t); break;
    case ObstacleCourse::kSlope: slope(t); break;
    case ObstacleCourse::kRubble: rubble(t); break;
    case ObstacleCourse::kDownUpStairs: down_up_stairs(t); break;
    case ObstacleCourse::kManyPipes: many_pipes(t); break;
    case ObstacleCourse::kDitch: ditch(t); break;
    case ObstacleCourse::kThickPipe: pipe(t, 0.10, 0.6); break;
    case ObstacleCourse::kThinPipe: pipe(t, 0.06, 0.4); break;
  }
  return t.done();
}

}  // namespace qdmeta::rhex
