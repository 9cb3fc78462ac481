#include "qdmeta/core/task.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/seconds_since.hpp"

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

// The text of the exception in flight (inside a catch block).
std::string what_of_current_exception() {
  try {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

}  // namespace

// A task's own exception names the batch row that threw: the block's rows are evaluated again one
// by one until one throws. For a task that evaluates its rows in order this costs about what the
// failed call did before it threw; the search gives up after twice that (at least a second),
// naming the block's rows instead.
void Task::evaluate_naming_failures(GenotypeView genotypes, EvaluationView out) const {
  const auto start = std::chrono::steady_clock::now();
  try {
    impl_->evaluate(genotypes, out);
  } catch (const Error&) {
    throw;  // qdmeta's own: it already says what failed
  } catch (...) {
    if (impl_->own_errors) throw;
    const double failed_call = seconds_since(start);
    const std::string what = what_of_current_exception();
    long long row = genotypes.count == 1 ? genotypes.first_row : -1;
    const auto search = std::chrono::steady_clock::now();
    for (Index i = 0; row < 0 && genotypes.count > 1 && i < genotypes.count; ++i) {
      if (seconds_since(search) > std::max(1.0, 2 * failed_call)) break;
      try {
        impl_->evaluate(genotypes.rows(i, 1), out.rows(i, 1));
      } catch (...) {
        row = genotypes.first_row + i;
      }
    }
    const std::string where =
        row >= 0 ? fmt::format("row {} of the batch", row)
                 : fmt::format("rows {}-{} of the batch (no row threw alone, or the search for it ran out of time)",
                               genotypes.first_row, genotypes.first_row + genotypes.count - 1);
    throw TaskFailed(fmt::format("task '{}' threw on {}: {}", name(), where, what), name(), row);
  }
}

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
  evaluate_naming_failures(genotypes, out);
  if (all_outputs_in_range(out)) return;
  for (Index i = 0; i < out.count; ++i) {
    if (!out.valid[i]) continue;
    if (!std::isfinite(out.fitness[i]))
      throw Error(fmt::format("task '{}': fitness of solution {} is {}", name(), genotypes.first_row + i,
                                out.fitness[i]));
    const Real* b = out.base_row(i);
    for (Index j = 0; j < out.base_feature_size; ++j)
      if (!(b[j] >= 0 && b[j] <= 1))
        throw Error(fmt::format("task '{}': base feature {} of solution {} is {}, outside [0, 1]{}", name(), j,
                                genotypes.first_row + i, b[j], kBaseFeatureRangeHint));
  }
}

}  // namespace qdmeta
