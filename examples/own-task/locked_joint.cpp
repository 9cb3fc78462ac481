#include "locked_joint.hpp"

#include <qdmeta/eval/evaluator.hpp>

#include <algorithm>
#include <cmath>

#include "arm_task.hpp"

namespace arm {
namespace {

qdmeta::Vector fitness_of(const qdmeta::Task& arm, const qdmeta::RowMatrix& genotypes, qdmeta::Evaluator& evaluator) {
  qdmeta::EvaluationBatch batch;
  batch.resize(genotypes.rows(), arm.base_feature_size());
  evaluator.evaluate(arm, {genotypes.data(), genotypes.rows(), genotypes.cols()}, batch.view());
  return batch.fitness;
}

}  // namespace

qdmeta::RowMatrix with_joint_locked(qdmeta::RowMatrix genotypes, int joint) {
  genotypes.col(joint).setConstant(kStraightGene);
  return genotypes;
}

LockedJointMeta::LockedJointMeta(qdmeta::Task arm, int joint, double sample_fraction)
    : arm_(std::move(arm)), joint_(joint), sample_fraction_(sample_fraction) {}

qdmeta::MetaPlan LockedJointMeta::plan(const qdmeta::MetaArchive& archive, qdmeta::Rng& rng) const {
  const qdmeta::RowMatrix& elites = archive.genotypes();
  qdmeta::MetaPlan plan;
  if (elites.rows() == 0) return plan;
  const auto size = std::max<qdmeta::Index>(1, std::lround(sample_fraction_ * static_cast<double>(elites.rows())));
  qdmeta::RowMatrix sample(size, elites.cols());
  for (qdmeta::Index i = 0; i < size; ++i)  // with replacement: simple, and unbiased for the mean
    sample.row(i) = elites.row(static_cast<qdmeta::Index>(rng.below(static_cast<std::uint64_t>(elites.rows()))));
  plan.batches.push_back({0, with_joint_locked(std::move(sample), joint_)});
  return plan;
}

qdmeta::MetaFitnessResult LockedJointMeta::score(const qdmeta::MetaArchive& archive, const qdmeta::MetaPlan& plan,
                                                 std::span<const qdmeta::EvaluationBatch> results) const {
  if (plan.batches.empty()) return {};
  // The mean score (fitness above the worst) times the archive's size: an archive is rewarded
  // for elites that work with the joint locked, and for having many of them.
  const qdmeta::Vector& fitness = results[0].fitness;
  const double mean_score = fitness.cast<double>().mean() - kWorstFitness;
  return {mean_score * static_cast<double>(archive.size()), fitness.size()};
}

void LockedJointTests::score(qdmeta::Index test, const qdmeta::RowMatrix& genotypes, qdmeta::Evaluator& evaluator,
                             std::span<double> out) const {
  const qdmeta::Vector fitness = fitness_of(arm_, with_joint_locked(genotypes, static_cast<int>(test)), evaluator);
  for (qdmeta::Index i = 0; i < fitness.size(); ++i) out[static_cast<std::size_t>(i)] = fitness[i];
}

std::unique_ptr<qdmeta::MetaObjective> read_locked_joint(qdmeta::ConfigReader& meta_fitness, const qdmeta::Task& task,
                                                         std::uint64_t /*seed*/) {
  const auto joint = meta_fitness.integer("joint", 0, 0, task.genotype_size() - 1);
  const double fraction = meta_fitness.number("sample_fraction", 0.1, 0.0, 1.0, qdmeta::Open::kLower);
  return std::make_unique<LockedJointMeta>(task, static_cast<int>(joint), fraction);
}

}  // namespace arm
