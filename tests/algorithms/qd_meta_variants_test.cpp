// QD-Meta with the authors' variants (docs/fidelity.md): lambda = 1 as their C CMA-ES realised it,
// and their Rastrigin database's 2g - 1 inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <span>
#include <utility>

#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "small_qd_meta.hpp"

namespace qdmeta {
namespace {

QdMeta variant_qd_meta(CmaSmallPopulation small, Index meta_population = 1,
                     DatabaseInputs inputs = DatabaseInputs::kBaseFeatures) {
  QdMetaParams p = small_qd_meta_params();
  p.meta_population = meta_population;
  p.database_inputs = inputs;
  p.cma_small_population = small;
  return small_qd_meta_of(p, 3, std::make_unique<StaticControl>(2));
}

// One map per meta-generation (the bottom-level budget of a (1,1)-ES), while CMA-ES samples
// c-cmaes's default population and recombines the map's sample with the unevaluated ones.
TEST(QdMetaAuthorsLambdaOne, RunsOneMapAndRecombinesTheLibraryPopulation) {
  SerialEvaluator evaluator;
  QdMeta authors = variant_qd_meta(CmaSmallPopulation::kAuthors);
  QdMeta one_one = variant_qd_meta(CmaSmallPopulation::kOneOne);
  authors.step(evaluator);
  one_one.step(evaluator);
  EXPECT_EQ(authors.counters().bottom, 200 + 2 * 50);
  EXPECT_EQ(authors.counters().bottom, one_one.counters().bottom);
  ASSERT_EQ(authors.meta_fitness().size(), 1U);

  // K = 10 x 6 + 1 + 2 x 10 + 1 = 82: lambda = 4 + floor(3 ln 82) = 4 + 13 = 17, mu = 8.
  const CmaEs& cma = authors.cma_es();
  ASSERT_EQ(cma.strategy().lambda, 17);
  const Eigen::MatrixXd& x = cma.state().samples;  // the last ask's samples; the mean was 0
  const double f = authors.meta_fitness()[0];
  ASSERT_NE(f, 0.0);
  // A positive meta-fitness ranks the map's sample first, then the unevaluated 16, 15, ...;
  // a negative one ranks it after all of them.
  const int first = f > 0 ? 0 : 16;
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(x.rows());
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) sum += std::log(9.0) - std::log(k + 1.0);
  for (int k = 0; k < 8; ++k) {
    const int column = f > 0 ? (k == 0 ? 0 : 17 - k) : first - k;
    expected += ((std::log(9.0) - std::log(k + 1.0)) / sum) * x.col(column);
  }
  EXPECT_LT((cma.state().mean - expected).cwiseAbs().maxCoeff(), 1e-12);
  // The map was built from the evaluated sample (clamped): its weights are column 0.
  EXPECT_LE(x.col(0).cwiseAbs().maxCoeff(), 1.0);
}

// Rastrigin's base features are the genotype g. Returns how many elites of `archive` store g and
// how many 2g - 1 (the authors' -1 + 2 g in single precision), and checks that every elite's
// measures are the map of what it stores (the network written out apart from the archive code).
std::pair<int, int> stored_inputs(const GridArchive& archive, const NeuralFeatureMap& map) {
  const EliteTable t = archive.elites();
  int plain = 0, shifted = 0;
  for (Index i = 0; i < t.size(); ++i) {
    bool is_plain = true, is_shifted = true;
    for (Index j = 0; j < t.solutions.cols(); ++j) {
      const Real g = t.solutions(i, j);
      is_plain = is_plain && t.base_features(i, j) == g;
      is_shifted = is_shifted && t.base_features(i, j) == Real{-1} + Real{2} * g;
    }
    plain += is_plain ? 1 : 0;
    shifted += is_shifted && !is_plain ? 1 : 0;
    Vector out(map.output_size());
    map.map(t.base_features.row(i).data(), 1, out.data());
    for (Index k = 0; k < out.size(); ++k) EXPECT_NEAR(t.measures(i, k), out(k), 1e-5) << "elite " << i;
  }
  return {plain, shifted};
}

NeuralFeatureMap map_of(const QdMeta& q, Index i) {
  NeuralFeatureMapShape shape;
  shape.inputs = 6;
  shape.hidden = 10;
  shape.outputs = 2;
  shape.alpha = 30.0;
  const Eigen::VectorXd w = q.cma_es().state().samples.col(i);
  return NeuralFeatureMap(shape, std::span<const double>(w.data(), static_cast<std::size_t>(w.size())));
}

// The database stores 2g - 1, so maps rebuilt from it place those inputs, while a meta-generation's
// fresh offspring are placed (and kept in the map) from g; the default stores and maps g only.
TEST(QdMetaAuthorsDatabaseInputs, RebuiltMapsReadTwoGMinusOneAndFreshOffspringG) {
  SerialEvaluator evaluator;
  QdMeta authors = variant_qd_meta(CmaSmallPopulation::kOneOne, 3, DatabaseInputs::kAuthors2gMinus1);
  QdMeta plain = variant_qd_meta(CmaSmallPopulation::kOneOne, 3);
  for (int t = 0; t < 2; ++t) {
    authors.step(evaluator);
    plain.step(evaluator);
  }
  const Database& db = authors.database();
  ASSERT_EQ(db.size(), 200 + 2 * 3 * 2 * 50);
  for (Index r = 0; r < db.size(); ++r)
    for (Index j = 0; j < 6; ++j) ASSERT_EQ(db.base_features(r)[j], Real{-1} + Real{2} * db.genotype(r)[j]);
  for (Index r = 0; r < plain.database().size(); ++r)
    for (Index j = 0; j < 6; ++j) ASSERT_EQ(plain.database().base_features(r)[j], plain.database().genotype(r)[j]);
  for (Index i = 0; i < 3; ++i) {
    const auto [fresh, rebuilt] = stored_inputs(authors.map_archives()[static_cast<std::size_t>(i)], map_of(authors, i));
    EXPECT_GT(fresh, 0) << "map " << i;
    EXPECT_GT(rebuilt, 0) << "map " << i;
    const auto [plain_fresh, plain_shifted] =
        stored_inputs(plain.map_archives()[static_cast<std::size_t>(i)], map_of(plain, i));
    EXPECT_EQ(plain_shifted, 0);
    EXPECT_EQ(plain_fresh, plain.map_archives()[static_cast<std::size_t>(i)].elites().size());
  }
}

}  // namespace
}  // namespace qdmeta
