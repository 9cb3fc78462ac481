#pragma once
// Owning storage for one batch of evaluations, whose view() a task writes into (core/task.hpp).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct EvaluationBatch {
  Vector fitness;
  RowMatrix base_features;
  std::vector<std::uint8_t> valid;
  void resize(Index count, Index base_feature_size) {
    fitness.resize(count);
    base_features.resize(count, base_feature_size);
    valid.assign(static_cast<std::size_t>(count), 0);
  }
  Index size() const { return fitness.size(); }
  EvaluationView view() {
    return {fitness.data(), base_features.data(), valid.data(), fitness.size(), base_features.cols()};
  }
};

}  // namespace qdmeta
