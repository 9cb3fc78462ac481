#pragma once
// The planar arm, a classic QD task: n joints on links whose lengths sum to 1. Genes in [0, 1]
// are joint angles in [-pi, pi]; fitness = minus the variance of the angles (smooth arms are
// better); base features = the end effector's (x, y), scaled from [-1, 1] to [0, 1].
#include <qdmeta/core/task.hpp>

#include <numbers>
#include <string>

namespace arm {

// The gene that puts a joint at angle 0 (straight).
inline constexpr qdmeta::Real kStraightGene = 0.5f;
// The lowest fitness: the variance of angles in [-pi, pi] is at most pi^2.
inline constexpr double kWorstFitness = -std::numbers::pi * std::numbers::pi;

class ArmTask {
 public:
  explicit ArmTask(int joints = 10);
  std::string name() const { return "arm"; }
  qdmeta::Index genotype_size() const { return joints_; }
  qdmeta::Index base_feature_size() const { return 2; }
  bool shareable() const { return true; }  // stateless: one instance serves every thread
  double qd_offset() const { return kWorstFitness; }  // so that every elite adds to the QD-score
  void evaluate(qdmeta::GenotypeView genotypes, qdmeta::EvaluationView out) const;

 private:
  int joints_;
};

}  // namespace arm
