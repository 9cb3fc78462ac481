#include "qdmeta/core/task.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

void Task::validate_sizes() const {
  if (genotype_size() < 1)
    throw InputError(fmt::format("task '{}': genotype size must be at least 1, got {}", name(), genotype_size()));
  if (base_feature_size() < 0)
    throw InputError(fmt::format("task '{}': base-feature size must be at least 0, got {}", name(),
                                 base_feature_size()));
}

namespace {

// Fast pass over the whole block, as two flat loops without early exits (they vectorise): true
// when every fitness is finite and every base feature in [0, 1], whatever the valid flags say.
// Only when it fails does the slow pass look at each row (invalid rows may hold anything).
bool all_outputs_in_range(const EvaluationView& out) {
  int ok = 1;  // an int: GCC does not vectorise a bool reduction
  for (Index i = 0; i < out.count; ++i) ok &= std::abs(out.fitness[i]) <= std::numeric_limits<Real>::max();  // NaN fails
  const Real* b = out.base_features;
  const Index total = out.count * out.base_feature_size;
  for (Index k = 0; k < total; ++k) ok &= (b[k] >= 0) & (b[k] <= 1);  // NaN fails
  return ok != 0;
}

}  // namespace

void Task::evaluate(GenotypeView genotypes, EvaluationView out) const {
  if (genotypes.genotype_size != genotype_size())
    throw Error(fmt::format("task '{}': genotypes have {} genes, the task expects {}", name(),
                            genotypes.genotype_size, genotype_size()));
  if (out.base_feature_size != base_feature_size())
    throw Error(fmt::format("task '{}': output has room for {} base features, the task writes {}", name(),
                            out.base_feature_size, base_feature_size()));
  if (out.count != genotypes.count)
    throw Error(fmt::format("task '{}': {} genotypes but room for {} evaluations", name(), genotypes.count,
                            out.count));
  impl_->evaluate(genotypes, out);
  if (all_outputs_in_range(out)) return;
  for (Index i = 0; i < out.count; ++i) {
    if (!out.valid[i]) continue;
    if (!std::isfinite(out.fitness[i]))
      throw Error(fmt::format("task '{}': fitness of solution {} is {}", name(), i, out.fitness[i]));
    const Real* b = out.base_row(i);
    for (Index j = 0; j < out.base_feature_size; ++j)
      if (!(b[j] >= 0 && b[j] <= 1))
        throw Error(fmt::format("task '{}': base feature {} of solution {} is {}, outside [0, 1]{}", name(), j, i,
                                b[j], kBaseFeatureRangeHint));
  }
}

}  // namespace qdmeta
