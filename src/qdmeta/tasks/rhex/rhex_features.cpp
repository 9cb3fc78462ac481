#include "qdmeta/tasks/rhex/rhex_features.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace qdmeta::rhex {
namespace {

using std::numbers::pi;

// Empirical maximum absolute change per 0.5 s interval (the authors' values).
constexpr std::array<double, 5> kMaxDeviation{1.05, 1.15, 1.05, 1.55, 1.27};
constexpr double kOrientationThreshold = 0.005 * pi;

double wrap_angle(double a) { return a - 2.0 * pi * std::floor((a + pi) / (2.0 * pi)); }

Real unit_clip(double v) { return static_cast<Real>(std::clamp(v, 0.0, 1.0)); }

}  // namespace

void trajectory_features(const std::vector<RelativePose>& samples, Real* out) {
  for (int k = 0; k + 1 < kTrajectorySamples; ++k) {
    const RelativePose& a = samples[k];
    const RelativePose& b = samples[k + 1];
    const std::array<double, 5> delta{b.x - a.x, b.y - a.y, wrap_angle(b.roll - a.roll),
                                      wrap_angle(b.pitch - a.pitch), wrap_angle(b.yaw - a.yaw)};
    for (int j = 0; j < 5; ++j) out[5 * k + j] = unit_clip((1.0 + delta[j] / kMaxDeviation[j]) / 2.0);
  }
}

void FeatureSetCounts::add_orientation(const RelativePose& pose) {
  const std::array<double, 3> angles{pose.roll, pose.pitch, pose.yaw};
  for (int j = 0; j < 3; ++j) {
    orientation[2 * j] += angles[j] > kOrientationThreshold;
    orientation[2 * j + 1] += angles[j] < -kOrientationThreshold;
  }
}

void feature_set_features(const FeatureSetCounts& counts, Real* out) {
  const double n = std::max(1, counts.samples);
  for (int i = 0; i < kLegs; ++i) out[i] = unit_clip(counts.leg_contact[i] / n);
  for (int j = 0; j < 6; ++j) out[6 + j] = unit_clip(counts.orientation[j] / n);
  const std::array<double, 3> v{counts.velocity_sum[0] / n, counts.velocity_sum[1] / n, counts.velocity_sum[2] / n};
  out[12] = unit_clip((v[0] - 0.108) / 1.188);
  out[13] = unit_clip((v[1] + 0.39) / 0.78);
  out[14] = unit_clip((v[2] + 0.03475) / 0.0695);
}

}  // namespace qdmeta::rhex
