// The test phase's random search: without replacement, uniform, best-so-far curves, mean and SE
// over test functions, determinism; and the Rastrigin test functions it runs.
#include "qdmeta/experiment/adaptation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "../expect_input_error.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rastrigin/test_functions.hpp"

namespace qdmeta {
namespace {

// Test function t scores a solution as gene 0 + t, and remembers which solutions it saw.
class ShiftedFirstGene final : public AdaptationTests {
 public:
  explicit ShiftedFirstGene(Index functions) : functions_(functions) {}
  std::string name() const override { return "shifted"; }
  Index count() const override { return functions_; }
  void score(Index test, const RowMatrix& genotypes, Evaluator&, std::span<double> out) const override {
    seen.emplace_back();
    for (Index r = 0; r < genotypes.rows(); ++r) {
      out[static_cast<std::size_t>(r)] = genotypes(r, 0) + static_cast<double>(test);
      seen.back().push_back(genotypes(r, 0));
    }
  }
  mutable std::vector<std::vector<double>> seen;

 private:
  Index functions_;
};

RowMatrix ladder(Index rows) {  // gene 0 = 1, 2, ..., rows: every solution distinct
  RowMatrix a(rows, 2);
  for (Index r = 0; r < rows; ++r) a.row(r) << static_cast<Real>(r + 1), 0.5f;
  return a;
}

TEST(Adaptation, SearchesWithoutReplacementAndKeepsTheBestSoFar) {
  SerialEvaluator evaluator;
  ShiftedFirstGene tests(4);
  const AdaptationCurve c = random_search_adaptation(ladder(50), tests, 30, 7, evaluator);
  ASSERT_EQ(c.best_mean.size(), 30u);
  ASSERT_EQ(tests.seen.size(), 4u);
  for (const auto& seen : tests.seen) {
    EXPECT_EQ(seen.size(), 30u);
    EXPECT_EQ(std::set<double>(seen.begin(), seen.end()).size(), 30u);  // no solution twice
  }
  for (std::size_t e = 1; e < 30; ++e) EXPECT_GE(c.best_mean[e], c.best_mean[e - 1]);
  // Mean and SE over functions, from the recorded orders independently.
  for (std::size_t e : {0u, 9u, 29u}) {
    std::vector<double> best;
    for (std::size_t t = 0; t < 4; ++t)
      best.push_back(*std::max_element(tests.seen[t].begin(), tests.seen[t].begin() + static_cast<long>(e) + 1) +
                     static_cast<double>(t));
    double mean = 0.0, sq = 0.0;
    for (double b : best) mean += b / 4.0;
    for (double b : best) sq += (b - mean) * (b - mean);
    EXPECT_NEAR(c.best_mean[e], mean, 1e-12);
    EXPECT_NEAR(c.best_se[e], std::sqrt(sq / 3.0) / 2.0, 1e-12);
  }
}

TEST(Adaptation, ASmallArchiveIsExhaustedAndItsBestCarriedForward) {
  SerialEvaluator evaluator;
  ShiftedFirstGene tests(3);
  const AdaptationCurve c = random_search_adaptation(ladder(5), tests, 12, 1, evaluator);
  ASSERT_EQ(c.best_mean.size(), 12u);
  for (std::size_t e = 4; e < 12; ++e) EXPECT_DOUBLE_EQ(c.best_mean[e], 5.0 + 1.0);  // max 5, shifts 0,1,2
  EXPECT_EQ(c.final_best, (std::vector<double>{5.0, 6.0, 7.0}));
}

TEST(Adaptation, OrdersAreUniformAtRandom) {
  // Over many functions, the best of the first k draws from {1, 2, 3} without replacement has
  // mean 2 (k = 1), 8/3 (k = 2) and 3 (k = 3). With replacement, k = 2 would give 23/9.
  SerialEvaluator evaluator;
  const Index functions = 6000;
  ShiftedFirstGene tests(functions);
  const AdaptationCurve c = random_search_adaptation(ladder(3), tests, 3, 11, evaluator);
  const double shift = static_cast<double>(functions - 1) / 2.0;  // mean of t
  EXPECT_NEAR(c.best_mean[0] - shift, 2.0, 0.03);
  EXPECT_NEAR(c.best_mean[1] - shift, 8.0 / 3.0, 0.03);
  EXPECT_DOUBLE_EQ(c.best_mean[2] - shift, 3.0);
}

TEST(Adaptation, SameSeedSameCurveOtherSeedOtherOrders) {
  SerialEvaluator serial;
  auto threads = make_evaluator(2);
  ShiftedFirstGene a(5), b(5), c(5);
  const auto x = random_search_adaptation(ladder(100), a, 10, 3, serial);
  const auto y = random_search_adaptation(ladder(100), b, 10, 3, *threads);
  const auto z = random_search_adaptation(ladder(100), c, 10, 4, serial);
  EXPECT_EQ(x.best_mean, y.best_mean);
  EXPECT_EQ(a.seen, b.seen);
  EXPECT_NE(a.seen, c.seen);
}

TEST(Adaptation, RejectsAnEmptyArchiveOrBudget) {
  SerialEvaluator evaluator;
  ShiftedFirstGene tests(2);
  EXPECT_INPUT_ERROR(random_search_adaptation(RowMatrix(0, 2), tests, 5, 1, evaluator), "test 'shifted': the archive is empty");
  EXPECT_INPUT_ERROR(random_search_adaptation(ladder(3), tests, 0, 1, evaluator),
                     "test 'shifted': budget 0 must be at least 1");
}

TEST(Generalisation, IsTheMeanOverSolutionsAndEnvironmentsWithSeOverEnvironments) {
  SerialEvaluator evaluator;
  ShiftedFirstGene tests(3);  // environment t scores gene 0 + t
  const GeneralisationRow row = whole_archive_mean(ladder(4), tests, evaluator);  // genes 1..4: mean 2.5
  EXPECT_EQ(row.group, "shifted");
  EXPECT_EQ(row.environments, 3);
  EXPECT_EQ(row.solutions, 4);
  EXPECT_DOUBLE_EQ(row.mean, 2.5 + 1.0);  // environment means 2.5, 3.5, 4.5
  EXPECT_DOUBLE_EQ(row.se, 1.0 / std::sqrt(3.0));  // SD 1 over 3 environments
  ASSERT_EQ(tests.seen.size(), 3u);
  for (const auto& seen : tests.seen) EXPECT_EQ(seen.size(), 4u);  // every solution, no search
  EXPECT_INPUT_ERROR(whole_archive_mean(RowMatrix(0, 2), tests, evaluator), "test 'shifted': the archive is empty");
}

TEST(RastriginTests, DimensionTestsUse120DistinctPairsAndClipAtMinusM) {
  Rng rng(5);
  RastriginDimensionTests tests(20, 120, rng);
  std::set<std::array<int, 2>> pairs(tests.pairs().begin(), tests.pairs().end());
  EXPECT_EQ(pairs.size(), 120u);
  for (const auto& p : pairs) EXPECT_LT(p[0], p[1]);
  Rng g(6);
  RowMatrix genotypes(8, 20);
  for (Index k = 0; k < genotypes.size(); ++k) genotypes.data()[k] = static_cast<Real>(g.uniform());
  std::vector<double> scores(8);
  SerialEvaluator evaluator;
  tests.score(17, genotypes, evaluator, scores);
  for (Index r = 0; r < 8; ++r)
    EXPECT_DOUBLE_EQ(scores[static_cast<std::size_t>(r)],
                     std::max(-2000.0, rastrigin::dimension_test({genotypes.row(r).data(), 20}, tests.pairs()[17])));
  Rng too_many(1);
  EXPECT_THROW(RastriginDimensionTests(4, 7, too_many), InputError);  // only 6 pairs of 4 dimensions
}

TEST(RastriginTests, TranslationTestsScoreTheGridWithOutOfRangeAsMinusM) {
  RastriginTranslationTests tests(20, 2000.0);
  ASSERT_EQ(tests.count(), 120);
  const auto grid = rastrigin::translation_test_grid();
  RowMatrix genotypes(2, 20);
  genotypes.row(0).setConstant(0.5f);  // x = 0: x' = b, in range for every grid point
  genotypes.row(1).setConstant(1.0f);  // x = 5.12: out of range once |a| > 1 or b pushes it out
  SerialEvaluator evaluator;
  std::vector<double> scores(2);
  int out_of_range = 0;
  for (Index t = 0; t < 120; ++t) {
    tests.score(t, genotypes, evaluator, scores);
    const auto& tr = grid[static_cast<std::size_t>(t)];
    EXPECT_DOUBLE_EQ(scores[0], *rastrigin::translated({genotypes.row(0).data(), 20}, tr.a, tr.b));
    const auto f = rastrigin::translated({genotypes.row(1).data(), 20}, tr.a, tr.b);
    EXPECT_DOUBLE_EQ(scores[1], f ? std::max(-2000.0, *f) : -2000.0);
    out_of_range += !f.has_value();
  }
  EXPECT_GT(out_of_range, 0);
}

}  // namespace
}  // namespace qdmeta
