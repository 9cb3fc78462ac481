#pragma once
// Points for CVT centroids taken from the task itself (docs/specification.md, CVT-MAP-Elites, RHex: "4,096 centroids
// over 100,000 feasible trajectories from random controllers"): the base features of random
// genotypes, invalid ("dead") ones skipped, so the cells follow the descriptors a task can
// actually produce instead of filling [0,1]^d uniformly.
#include <cstdint>

#include "qdmeta/core/evaluator.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

struct DescriptorPoints {
  RowMatrix points;     // count x base_feature_size, in draw order
  Index attempts = 0;   // random genotypes evaluated to find them
};

// The base features of the first `count` valid genotypes drawn uniformly in [0,1]^n, batch b
// from the stream (seed, kCentroids, 3, b), evaluated `batch` at a time on `evaluator`. Gives up
// with Error after `max_attempts` genotypes (too few feasible ones).
DescriptorPoints feasible_random_descriptors(const Task& task, Index count, std::uint64_t seed, Evaluator& evaluator,
                                             Index max_attempts, Index batch = 1000);

}  // namespace qdmeta
