#pragma once
// Rastrigin as a Task: fitness = standard Rastrigin, base features = the genotype itself.
#include <string>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/core/task_shape.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {

struct RastriginParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr IntParam kDimensions{"task", "dimensions", 1, 10'000,
      "Rastrigin: genotype size N; base features = genotype"};
  static constexpr RealParam kScoreM{"task", "score_m", 0.0, kNoUpper, Open::kLower,
      "Rastrigin: M of the per-task score M + max(-M, f); the QD-score offset is -M"};
  int dimensions = 20;                        // N, genotype size, in [1, 10000]
  double score_m = rastrigin::kDefaultScoreM;  // M: scores are M + max(-M, f); QD-score offset is -M
  void validate() const;
};

class RastriginTask {
 public:
  explicit RastriginTask(RastriginParams params = {});
  // What the accessors below return, without a task (a resolved config's, core/task_shape.hpp).
  static TaskShape shape_of(const RastriginParams& p) { return {"rastrigin", p.dimensions, p.dimensions, -p.score_m}; }
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
