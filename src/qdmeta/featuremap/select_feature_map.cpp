#include "qdmeta/featuremap/select_feature_map.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

SelectFeatureMap::SelectFeatureMap(Index input_size, std::vector<int> indices)
    : input_size_(input_size), indices_(std::move(indices)) {
  if (indices_.empty()) throw InputError("archive.measures is empty: name at least one base feature");
  for (int i : indices_)
    if (i < 0 || i >= input_size_)
      throw InputError(fmt::format("archive.measures: base feature {} does not exist (the task has {}, numbered 0 to {})",
                                   i, input_size_, input_size_ - 1));
}

void SelectFeatureMap::map(const Real* base, Index count, Real* target) const {
  const auto nt = static_cast<Index>(indices_.size());
  for (Index r = 0; r < count; ++r)
    for (Index k = 0; k < nt; ++k) target[r * nt + k] = base[r * input_size_ + indices_[static_cast<std::size_t>(k)]];
}

}  // namespace qdmeta
