#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <vector>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void RastriginParams::validate() const {
  require_range("task.dimensions", dimensions, 1, 10000);
  if (!(score_m > 0 && std::isfinite(score_m)))
    throw InputError(fmt::format("task.score_m = {} is out of range: must be a positive number", score_m));
}

RastriginTask::RastriginTask(RastriginParams params) : params_(params) { params_.validate(); }

void RastriginTask::evaluate(GenotypeView genotypes, EvaluationView out) const {
  thread_local std::vector<Real> scratch;
  rastrigin::evaluate_batch(genotypes.data, genotypes.count, genotypes.genotype_size, out.fitness, scratch);
  std::copy_n(genotypes.data, genotypes.count * genotypes.genotype_size, out.base_features);
  std::fill_n(out.valid, out.count, std::uint8_t{1});
}

}  // namespace qdmeta
