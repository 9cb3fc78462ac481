#pragma once
// What "adapting to damage" means for the arm: a joint locked straight (angle 0). The
// meta-objective scores an archive by the QD-score it would have with one joint locked,
// estimated from a sample of its elites re-evaluated so; the test family locks each joint in turn.
#include <qdmeta/core/adaptation_tests.hpp>
#include <qdmeta/core/meta_objective.hpp>
#include <qdmeta/plugin/config.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace arm {

// A copy of `genotypes` with gene `joint` forced straight.
qdmeta::RowMatrix with_joint_locked(qdmeta::RowMatrix genotypes, int joint);

class LockedJointMeta final : public qdmeta::MetaObjective {
 public:
  LockedJointMeta(qdmeta::Task arm, int joint, double sample_fraction);
  std::string name() const override { return "arm-locked-joint"; }
  // The sample to re-evaluate, with the joint locked: one batch of tasks()[0].
  qdmeta::MetaPlan plan(const qdmeta::MetaArchive& archive, qdmeta::Rng& rng) const override;
  // The estimate from that batch's fitness.
  qdmeta::MetaFitnessResult score(const qdmeta::MetaArchive& archive, const qdmeta::MetaPlan& plan,
                                  std::span<const qdmeta::EvaluationBatch> results) const override;
  std::vector<qdmeta::Task> tasks() const override { return {arm_}; }

 private:
  qdmeta::Task arm_;
  int joint_;
  double sample_fraction_;
};

// Test function j (0 <= j < joints): the arm with joint j locked; the score is the fitness.
class LockedJointTests final : public qdmeta::AdaptationTests {
 public:
  explicit LockedJointTests(qdmeta::Task arm) : arm_(std::move(arm)) {}
  std::string name() const override { return "locked"; }
  qdmeta::Index count() const override { return arm_.genotype_size(); }
  void score(qdmeta::Index test, const qdmeta::RowMatrix& genotypes, qdmeta::Evaluator& evaluator,
             std::span<double> out) const override;

 private:
  qdmeta::Task arm_;
};

// [meta_fitness] kind = "locked-joint": keys `joint` (default 0) and `sample_fraction` (0.1).
std::unique_ptr<qdmeta::MetaObjective> read_locked_joint(qdmeta::ConfigReader& meta_fitness, const qdmeta::Task& task,
                                                         std::uint64_t seed);

}  // namespace arm
