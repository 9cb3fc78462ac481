#include "qdmeta/core/meta_objective.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluator.hpp"

namespace qdmeta {

void check_meta_plan(const MetaObjective& objective, const MetaPlan& plan, std::span<const Task> tasks) {
  for (std::size_t k = 0; k < plan.batches.size(); ++k) {
    const MetaBatch& b = plan.batches[k];
    if (b.task < 0 || b.task >= static_cast<Index>(tasks.size()))
      throw Error(fmt::format("meta-objective '{}': batch {} names task {}, but tasks() lists {}", objective.name(), k,
                              b.task, tasks.size()));
    const Task& task = tasks[static_cast<std::size_t>(b.task)];
    if (b.genotypes.cols() != task.genotype_size())
      throw Error(fmt::format("meta-objective '{}': batch {} has genotypes of {} genes, task '{}' expects {}",
                              objective.name(), k, b.genotypes.cols(), task.name(), task.genotype_size()));
  }
}

MetaFitnessResult MetaObjective::evaluate(const RowMatrix& elites, Rng& rng, Evaluator& evaluator) const {
  const MetaPlan planned = plan(elites, rng);
  const std::vector<Task> task_list = tasks();
  check_meta_plan(*this, planned, task_list);
  std::vector<EvaluationBatch> results(planned.batches.size());
  std::vector<EvaluationJob> jobs;
  for (std::size_t k = 0; k < planned.batches.size(); ++k) {
    const MetaBatch& b = planned.batches[k];
    const Task& task = task_list[static_cast<std::size_t>(b.task)];
    results[k].resize(b.genotypes.rows(), task.base_feature_size());
    jobs.push_back({&task, {b.genotypes.data(), b.genotypes.rows(), b.genotypes.cols()}, results[k].view()});
  }
  if (!jobs.empty()) evaluator.evaluate_jobs(jobs);
  return score(elites, planned, results);
}

}  // namespace qdmeta
