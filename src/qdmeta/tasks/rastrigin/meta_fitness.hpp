#pragma once
// QD-Meta's Rastrigin meta-fitnesses (docs/specification.md, Meta-objectives): the Dimension and the Translation
// meta-fitness of an archive. Both score a uniform sample of the archive's elites, drawn anew in
// each evaluation (docs/specification.md, QD-Meta), and sum the per-task scores M + max(-M, f) over it, so
// bigger archives score more. Higher is better.
//
// Both are analytic: plan() computes the result (no batches to simulate) and score() returns it.
// Random draws, in this order, all from the `rng` given to plan() (or evaluate()):
//   1. the sample: sample_elites(elites.rows(), meta_sample_size(fraction, elites.rows()), rng);
//   2. Translation only: one set of transforms, rastrigin::sample_meta_transforms(rng, repetitions);
//      with transform_per_solution, one such set per sampled solution, in sample order.
// Tests and callers can thus reproduce the exact sample and transforms from the same seed.
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/meta_objective.hpp"
#include "qdmeta/core/params.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {

struct RastriginMetaParams {
  // [meta_fitness] of the Rastrigin task (docs/config.md).
  static constexpr RealParam kSampleFraction{
      "meta_fitness", "sample_fraction", 0.0, 1.0, Open::kLower,
      "fraction of the archive scored, n = max(1, round(fraction x size)), drawn anew each time"};
  static constexpr IntParam kTransformRepetitions{"meta_fitness", "transform_repetitions", 1, 1000,
                                                  "translation: transforms per each of the 8 ranges (16 in all)"};
  // |J|; at most the task's genotype size besides, which the config reader checks (the one place
  // that knows it: read_dimension_meta).
  static constexpr IntParam kDimensionCount{"meta_fitness", "dimension_count", 1, 10'000,
                                            "dimension: the size of J, dimensions removed one at a time"};
  double sample_fraction = 0.10;                // share of the archive scored (kSampleFraction)
  double score_m = rastrigin::kDefaultScoreM;   // M: per-task scores are M + max(-M, f), M > 0 and finite
  int dimension_count = 10;                     // |J|: dimensions removed by the Dimension meta-fitness (kDimensionCount)
  int transform_repetitions = 2;                // Translation: transforms per each of the 8 ranges (kTransformRepetitions)
  bool transform_per_solution = false;          // Translation: a fresh set of transforms per solution (authors' code)
  void validate() const;                        // throws InputError naming the field, value and rule
};

// Sample size n = max(1, round(fraction x archive_size)), capped at archive_size; 0 for an empty archive.
Index meta_sample_size(double fraction, Index archive_size);

// `count` distinct row indices out of [0, archive_size), uniformly without replacement (partial
// Fisher-Yates: exactly `count` draws of rng.below), in draw order. Deterministic given the rng.
std::vector<Index> sample_elites(Index archive_size, Index count, Rng& rng);

// F = (1/|J|) [ sum_j sum_s score_j(s) + alpha sum_{s<t} ||g_s - g_t||_2 ], alpha = sqrt(N) M / (n - 1),
// with f_j the Rastrigin function without dimension j, and no diversity term when n < 2.
// evaluations = n |J|.
class RastriginDimensionMeta final : public MetaObjective {
 public:
  // `dimensions`: J, drawn once per replicate (rastrigin::sample_dimensions); dimension_count
  // of them, distinct and non-negative (checked against the genotype size in evaluate()).
  RastriginDimensionMeta(RastriginMetaParams params, std::vector<int> dimensions);
  // What the constructor checks, for a config that is only resolved: InputError on a bad value.
  static void validate(const RastriginMetaParams& params, const std::vector<int>& dimensions);
  std::string name() const override { return "rastrigin-dimension"; }
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override;
  MetaFitnessResult score(const MetaArchive& archive, const MetaPlan& plan,
                          std::span<const EvaluationBatch> results) const override;
  const RastriginMetaParams& params() const { return params_; }
  const std::vector<int>& dimensions() const { return dimensions_; }

 private:
  MetaFitnessResult compute(const RowMatrix& elites, Rng& rng) const;
  RastriginMetaParams params_;
  std::vector<int> dimensions_;
};

// F = (1/T) sum_T sum_s score_T(s), over T = 8 x transform_repetitions linear transforms
// x' = a x + b; score_T(s) = M + max(-M, f(x')) with f the standard Rastrigin function, and 0
// when any |x'_i| > 5.12. evaluations = n T.
class RastriginTranslationMeta final : public MetaObjective {
 public:
  explicit RastriginTranslationMeta(RastriginMetaParams params = {});
  std::string name() const override { return "rastrigin-translation"; }
  MetaPlan plan(const MetaArchive& archive, Rng& rng) const override;
  MetaFitnessResult score(const MetaArchive& archive, const MetaPlan& plan,
                          std::span<const EvaluationBatch> results) const override;
  const RastriginMetaParams& params() const { return params_; }
  int transform_count() const { return 8 * params_.transform_repetitions; }

 private:
  MetaFitnessResult compute(const RowMatrix& elites, Rng& rng) const;
  RastriginMetaParams params_;
};

// The diversity sum sum_{s<t} ||p_s - p_t||_2 over the rows of `points`, in double from the
// coordinate differences, every sum in an order the code fixes (the same bits on any CPU);
// memory O(rows x columns). 0 for fewer than 2 rows. Exposed for tests and benchmarks.
double pairwise_distance_sum(const Eigen::Ref<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>>& points);
// The same sums in plain loops: pairwise_distance_sum() on a CPU without AVX2 and FMA, and on
// one with them the bits that its vector steps (sixteen pairs at a time) reproduce (tested).
double pairwise_distance_sum_portable(
    const Eigen::Ref<const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>>& points);

}  // namespace qdmeta
