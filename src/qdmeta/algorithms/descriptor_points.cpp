#include "qdmeta/algorithms/descriptor_points.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {

DescriptorPoints feasible_random_descriptors(const Task& task, Index count, std::uint64_t seed, Evaluator& evaluator,
                                             Index max_attempts, Index batch) {
  if (count < 1 || batch < 1) throw InputError(fmt::format("descriptor points: count {} and batch {} must be >= 1", count, batch));
  const Index n = task.genotype_size();
  DescriptorPoints out;
  out.points.resize(count, task.base_feature_size());
  Index found = 0;
  RowMatrix genotypes;
  EvaluationBatch evaluations;
  for (std::uint64_t b = 0; found < count; ++b) {
    if (out.attempts >= max_attempts)
      throw Error(fmt::format("task '{}': only {} of {} random genotypes were valid, {} needed for the centroids "
                              "(lower cvt.samples or raise cvt.max_attempts)",
                              task.name(), found, out.attempts, count));
    // Batches are drawn whole whatever `count`, so a smaller count takes a prefix of the same points.
    const Index rows = std::min(batch, max_attempts - out.attempts);
    Rng rng = Rng::stream(seed, {key(StreamKey::kCentroids), 3, b});
    genotypes.resize(rows, n);
    for (Index i = 0; i < genotypes.size(); ++i) genotypes.data()[i] = static_cast<Real>(rng.uniform());
    evaluations.resize(rows, task.base_feature_size());
    evaluator.evaluate(task, {genotypes.data(), rows, n}, evaluations.view());
    out.attempts += rows;
    for (Index r = 0; r < rows && found < count; ++r)
      if (evaluations.valid[static_cast<std::size_t>(r)]) out.points.row(found++) = evaluations.base_features.row(r);
  }
  return out;
}

}  // namespace qdmeta
