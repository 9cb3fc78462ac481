#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

#include <algorithm>
#include <vector>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void RastriginParams::validate() const {
  require(kDimensions, dimensions);
  require(kScoreM, score_m);
}

RastriginTask::RastriginTask(RastriginParams params) : params_(params) { params_.validate(); }

void RastriginTask::evaluate(GenotypeView genotypes, EvaluationView out) const {
  thread_local std::vector<Real> scratch;
  rastrigin::evaluate_batch(genotypes.data, genotypes.count, genotypes.genotype_size, out.fitness, scratch);
  std::copy_n(genotypes.data, genotypes.count * genotypes.genotype_size, out.base_features);
  std::fill_n(out.valid, out.count, std::uint8_t{1});
}

}  // namespace qdmeta
