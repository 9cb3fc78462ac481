#include "qdmeta/tasks/rastrigin/test_functions.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

namespace {
void check(Index test, Index count, const RowMatrix& genotypes, int dimensions, std::span<double> out) {
  if (test < 0 || test >= count) throw Error(fmt::format("test function {} out of range [0, {})", test, count));
  if (genotypes.cols() != dimensions)
    throw Error(fmt::format("test functions of {}-D Rastrigin given {}-gene genotypes", dimensions, genotypes.cols()));
  if (static_cast<Index>(out.size()) != genotypes.rows()) throw Error("test scores: output size differs from rows");
}
}  // namespace

RastriginDimensionTests::RastriginDimensionTests(int dimensions, int pairs, Rng& rng, double score_m)
    : dimensions_(dimensions), score_m_(score_m) {
  const int possible = dimensions * (dimensions - 1) / 2;
  if (dimensions < 2 || pairs < 1 || pairs > possible)
    throw InputError(fmt::format("dimension test: {} distinct pairs of {} dimensions are impossible (at most {})", pairs,
                                 dimensions, possible));
  pairs_ = rastrigin::sample_dimension_pairs(rng, dimensions, pairs);
}

void RastriginDimensionTests::score(Index test, const RowMatrix& genotypes, Evaluator&, std::span<double> out) const {
  check(test, count(), genotypes, dimensions_, out);
  const auto& pair = pairs_[static_cast<std::size_t>(test)];
  for (Index r = 0; r < genotypes.rows(); ++r) {
    const double f = rastrigin::dimension_test({genotypes.row(r).data(), static_cast<std::size_t>(dimensions_)}, pair);
    out[static_cast<std::size_t>(r)] = std::max(-score_m_, f);
  }
}

RastriginTranslationTests::RastriginTranslationTests(int dimensions, double score_m)
    : dimensions_(dimensions), grid_(rastrigin::translation_test_grid()), score_m_(score_m) {
  if (dimensions < 1) throw InputError("translation test: the task has no dimensions");
}

void RastriginTranslationTests::score(Index test, const RowMatrix& genotypes, Evaluator&, std::span<double> out) const {
  check(test, count(), genotypes, dimensions_, out);
  const auto& t = grid_[static_cast<std::size_t>(test)];
  for (Index r = 0; r < genotypes.rows(); ++r) {
    const auto f = rastrigin::translated({genotypes.row(r).data(), static_cast<std::size_t>(dimensions_)}, t.a, t.b);
    out[static_cast<std::size_t>(r)] = f ? std::max(-score_m_, *f) : -score_m_;
  }
}

}  // namespace qdmeta
