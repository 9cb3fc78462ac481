#include "polar_feature_map.hpp"

#include <qdmeta/core/error.hpp>
#include <qdmeta/plugin/config.hpp>
#include <qdmeta/plugin/part_registries.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace arm {

PolarFeatureMap::PolarFeatureMap(double reach) : reach_(reach) {
  if (!(reach > 0)) throw qdmeta::InputError("feature-map \"polar\": reach must be > 0");
}

// Rows are independent: MAP-Elites hands over a whole batch, and may split it between threads.
void PolarFeatureMap::map(const qdmeta::Real* base, qdmeta::Index count, qdmeta::Real* target) const {
  for (qdmeta::Index r = 0; r < count; ++r) {
    const double x = 2.0 * base[2 * r] - 1, y = 2.0 * base[2 * r + 1] - 1;  // back to the arm's plane
    const double distance = std::min(std::hypot(x, y) / reach_, 1.0);
    const double direction = (std::atan2(y, x) + std::numbers::pi) / (2 * std::numbers::pi);
    target[2 * r] = static_cast<qdmeta::Real>(distance);
    target[2 * r + 1] = static_cast<qdmeta::Real>(std::clamp(direction, 0.0, 1.0));
  }
}

std::unique_ptr<qdmeta::FeatureMap> read_polar_feature_map(qdmeta::ConfigReader& feature_map,
                                                          qdmeta::Index base_features, qdmeta::Index target_features) {
  const double reach = feature_map.number("reach", 1.0, 0.0, 1e6, qdmeta::Open::kLower);
  if (base_features != 2 || target_features != 2)
    throw qdmeta::InputError("feature-map \"polar\" maps 2 base features to 2 target features, not " +
                             std::to_string(base_features) + " to " + std::to_string(target_features));
  return std::make_unique<PolarFeatureMap>(reach);
}

void register_polar_feature_map() { qdmeta::feature_map_registry().add("polar", read_polar_feature_map); }

}  // namespace arm
