#include "qdmeta/core/meta_objective.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/evaluator.hpp"

namespace qdmeta {

MetaArchive::MetaArchive(const RowMatrix& genotypes, const Vector& fitness, const RowMatrix& measures,
                         const RowMatrix& base_features)
    : genotypes_(&genotypes), fitness_(&fitness), measures_(&measures), base_features_(&base_features) {
  const Index n = genotypes.rows();
  if (fitness.size() != n || measures.rows() != n || base_features.rows() != n)
    throw Error(fmt::format("MetaArchive: {} genotypes but {} fitness values, {} measure rows and {} base-feature rows",
                            n, fitness.size(), measures.rows(), base_features.rows()));
}

namespace {
template <class T>
const T& stored(const T* value, const char* what) {
  if (value == nullptr)
    throw Error(fmt::format("MetaArchive: this archive holds genotypes only, no {} (QD-Meta's archives hold them)",
                            what));
  return *value;
}
}  // namespace

const Vector& MetaArchive::fitness() const { return stored(fitness_, "fitness"); }
const RowMatrix& MetaArchive::measures() const { return stored(measures_, "measures"); }
const RowMatrix& MetaArchive::base_features() const { return stored(base_features_, "base features"); }

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

MetaFitnessResult MetaObjective::evaluate(const MetaArchive& archive, Rng& rng, Evaluator& evaluator) const {
  const MetaPlan planned = plan(archive, rng);
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
  return score(archive, planned, results);
}

}  // namespace qdmeta
