#pragma once
// [feature_map] kind = "polar": the arm's end effector in polar coordinates, the archive's axes
// its distance from the arm's base (divided by `reach`) and its direction, where "select" would
// give its (x, y). docs/tutorials/feature-map.md builds it.
#include <qdmeta/featuremap/feature_map.hpp>

#include <memory>

namespace qdmeta {
class ConfigReader;
}

namespace arm {

// From the arm's two base features, (x + 1) / 2 and (y + 1) / 2, to two target features in
// [0, 1]: min(r / reach, 1) and (atan2(y, x) + pi) / (2 pi), where r = sqrt(x^2 + y^2).
class PolarFeatureMap final : public qdmeta::FeatureMap {
 public:
  explicit PolarFeatureMap(double reach);  // > 0
  qdmeta::Index input_size() const override { return 2; }
  qdmeta::Index output_size() const override { return 2; }
  void map(const qdmeta::Real* base, qdmeta::Index count, qdmeta::Real* target) const override;

 private:
  double reach_;
};

// [feature_map] kind = "polar": key `reach` (default 1, the arm's length; > 0). The task must have
// 2 base features and the archive 2 dimensions.
std::unique_ptr<qdmeta::FeatureMap> read_polar_feature_map(qdmeta::ConfigReader& feature_map,
                                                          qdmeta::Index base_features, qdmeta::Index target_features);

// Makes `[feature_map] kind = "polar"` available to configs (qdmeta's feature-map registry).
void register_polar_feature_map();

}  // namespace arm
