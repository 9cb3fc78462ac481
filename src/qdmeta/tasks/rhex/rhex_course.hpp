#pragma once
// The floor and obstacles of a course as a list of fixed shapes, engine-independent: DART
// (rhex_terrain.cpp) and MuJoCo (rhex_mjcf.cpp) build their static world from it. Internal to the
// rhex libraries.
#include "qdmeta/core/eigen.hpp"  // before any other Eigen header

#include <Eigen/Geometry>

#include <vector>

#include "qdmeta/tasks/rhex/rhex_environment.hpp"

namespace qdmeta::rhex {

struct TerrainShape {
  enum class Kind { kBox, kSphere } kind = Kind::kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box: full side lengths
  double radius = 0.0;                             // sphere
  Eigen::Isometry3d where = Eigen::Isometry3d::Identity();
};

// Floors are 0.2 m thick boxes with their top at z = 0 (docs/specification.md, RHex).
std::vector<TerrainShape> course_shapes(ObstacleCourse course);

}  // namespace qdmeta::rhex
