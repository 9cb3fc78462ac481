// QD-Meta with the authors' variants (docs/fidelity.md): lambda = 1 as their C CMA-ES realised it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/tasks/rastrigin/meta_fitness.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

QdMeta one_map_qd_meta(CmaSmallPopulation small) {
  RastriginParams rp;
  rp.dimensions = 6;
  QdMetaParams p;
  p.meta_population = 1;
  p.batch_size = 50;
  p.initial_population = 200;
  p.database_capacity = 3000;
  p.cma_small_population = small;
  GridArchiveParams grid;
  grid.bins = {20, 20};
  RastriginMetaParams mp;
  mp.sample_fraction = 0.5;
  return QdMeta(p, Task(RastriginTask(rp)), std::make_unique<RastriginTranslationMeta>(mp), grid, {},
                std::make_unique<StaticControl>(2), 3);
}

// One map per meta-generation (the bottom-level budget of a (1,1)-ES), while CMA-ES samples
// c-cmaes's default population and recombines the map's sample with the unevaluated ones.
TEST(QdMetaAuthorsLambdaOne, RunsOneMapAndRecombinesTheLibraryPopulation) {
  SerialEvaluator evaluator;
  QdMeta authors = one_map_qd_meta(CmaSmallPopulation::kAuthors);
  QdMeta one_one = one_map_qd_meta(CmaSmallPopulation::kOneOne);
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

}  // namespace
}  // namespace qdmeta
