#pragma once
// Rastrigin as a Task: fitness = standard Rastrigin, base features = the genotype itself.
#include <string>

#include "qdmeta/core/task.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {

struct RastriginParams {
  int dimensions = 20;                        // N, genotype size, in [1, 10000]
  double score_m = rastrigin::kDefaultScoreM;  // M: scores are M + max(-M, f); QD-score offset is -M
  void validate() const;
};

class RastriginTask {
 public:
  explicit RastriginTask(RastriginParams params = {});
  std::string name() const { return "rastrigin"; }
  Index genotype_size() const { return params_.dimensions; }
  Index base_feature_size() const { return params_.dimensions; }
  bool shareable() const { return true; }  // stateless apart from a per-thread scratch buffer
  double qd_offset() const { return -params_.score_m; }
  void evaluate(GenotypeView genotypes, EvaluationView out) const;
  const RastriginParams& params() const { return params_; }

 private:
  RastriginParams params_;
};

}  // namespace qdmeta
