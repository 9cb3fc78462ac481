#pragma once
// The fixed feature-map of plain MAP-Elites: target features are chosen base features,
// e.g. (g0, g1) on Rastrigin.
#include <vector>

#include "qdmeta/featuremap/feature_map.hpp"

namespace qdmeta {

class SelectFeatureMap final : public FeatureMap {
 public:
  // Throws InputError when an index is outside [0, input_size) or the list is empty.
  SelectFeatureMap(Index input_size, std::vector<int> indices);
  Index input_size() const override { return input_size_; }
  Index output_size() const override { return static_cast<Index>(indices_.size()); }
  void map(const Real* base, Index count, Real* target) const override;

 private:
  Index input_size_;
  std::vector<int> indices_;
};

}  // namespace qdmeta
