#pragma once
// The two base-feature spaces of the RHex task (docs/specification.md, RHex), computed from what an episode
// records. DART-free: tested on hand-made records.
#include <array>
#include <vector>

#include "qdmeta/core/types.hpp"
#include "qdmeta/tasks/rhex/buehler_clock.hpp"

namespace qdmeta::rhex {

inline constexpr Index kTrajectoryFeatures = 50;
inline constexpr Index kFeatureSetFeatures = 15;
inline constexpr int kTrajectorySamples = 11;  // t = 0, 0.5, ..., 5 s

// Body pose relative to the start pose: position difference in the world frame, and the XYZ
// Euler angles of R_start^-1 R.
struct RelativePose {
  double x = 0, y = 0, z = 0, roll = 0, pitch = 0, yaw = 0;
};

// 50-D trajectory: per interval (x, y, roll, pitch, yaw) differences between consecutive samples,
// each divided by its maximum deviation, mapped by (1 + d) / 2 and clipped to [0, 1]. Angle
// differences are wrapped to [-pi, pi). `samples` has kTrajectorySamples entries.
void trajectory_features(const std::vector<RelativePose>& samples, Real* out);

// Counts gathered every 10 ms for the 15-D feature-sets.
struct FeatureSetCounts {
  int samples = 0;
  std::array<int, kLegs> leg_contact{};    // samples in which any plate of leg i touches anything
  std::array<int, 6> orientation{};        // roll>, roll<, pitch>, pitch<, yaw>, yaw< (+-0.005 pi)
  std::array<double, 3> velocity_sum{};    // centre-of-mass velocity x, y, z summed over samples
  void add_orientation(const RelativePose& pose);
};

// 15-D feature-sets: 6 duty factors, 6 orientation fractions, 3 normalised mean velocities.
void feature_set_features(const FeatureSetCounts& counts, Real* out);

}  // namespace qdmeta::rhex
