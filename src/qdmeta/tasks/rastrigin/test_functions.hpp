#pragma once
// The Rastrigin test phase (docs/specification.md, Test phase): 120 dimension-noise functions (distinct pairs
// of dimensions replaced by 10 sin(6 pi x)) and the 120-point translation grid. Scores are
// max(-M, f), the per-task score minus M, so an out-of-range translation counts as -M.
#include <array>
#include <vector>

#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"

namespace qdmeta {

class RastriginDimensionTests final : public AdaptationTests {
 public:
  // `pairs` distinct unordered pairs of dimensions out of `dimensions`, drawn from rng.
  RastriginDimensionTests(int dimensions, int pairs, Rng& rng, double score_m = rastrigin::kDefaultScoreM);
  std::string name() const override { return "dimension"; }
  Index count() const override { return static_cast<Index>(pairs_.size()); }
  void score(Index test, const RowMatrix& genotypes, Evaluator& evaluator, std::span<double> out) const override;
  const std::vector<std::array<int, 2>>& pairs() const { return pairs_; }

 private:
  int dimensions_;
  std::vector<std::array<int, 2>> pairs_;
  double score_m_;
};

class RastriginTranslationTests final : public AdaptationTests {
 public:
  explicit RastriginTranslationTests(int dimensions, double score_m = rastrigin::kDefaultScoreM);
  std::string name() const override { return "translation"; }
  Index count() const override { return static_cast<Index>(grid_.size()); }
  void score(Index test, const RowMatrix& genotypes, Evaluator& evaluator, std::span<double> out) const override;

 private:
  int dimensions_;
  std::vector<rastrigin::LinearTransform> grid_;
  double score_m_;
};

}  // namespace qdmeta
