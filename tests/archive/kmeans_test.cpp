// Tests of src/qdmeta/archive/kmeans.{hpp,cpp}: known clusters are recovered, Lloyd's cost never
// rises, the same bits at any thread count, and parameter checks.
#include "qdmeta/archive/kmeans.hpp"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <limits>

#include "expect_input_error.hpp"
#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

// `per_cluster` points around each of `centres` (rows) with Gaussian noise of SD `sd`,
// interleaved so that no cluster is contiguous.
RowMatrix clustered_points(const RowMatrix& centres, Index per_cluster, double sd, std::uint64_t seed) {
  Rng rng(seed);
  RowMatrix points(centres.rows() * per_cluster, centres.cols());
  for (Index i = 0; i < points.rows(); ++i)
    for (Index j = 0; j < points.cols(); ++j)
      points(i, j) = centres(i % centres.rows(), j) + static_cast<Real>(sd * rng.normal());
  return points;
}

RowMatrix separated_centres() {
  // 8 corners of a cube in 3-D, scaled apart, plus 2 more coordinates.
  RowMatrix c(8, 5);
  for (Index i = 0; i < 8; ++i)
    c.row(i) << static_cast<Real>(i & 1), static_cast<Real>((i >> 1) & 1), static_cast<Real>((i >> 2) & 1), 0.5f,
        static_cast<Real>(i) / 8;
  return c;
}

void expect_recovers(const RowMatrix& found, const RowMatrix& truth, double tolerance) {
  ASSERT_EQ(found.rows(), truth.rows());
  std::vector<int> hits(static_cast<std::size_t>(truth.rows()), 0);
  for (Index i = 0; i < found.rows(); ++i) {
    const Index t = nearest_centroid_naive(truth, found.row(i).data());
    EXPECT_LT(std::sqrt(squared_distance(found.row(i).data(), truth.row(t).data(), truth.cols())), tolerance)
        << "centroid " << i;
    ++hits[static_cast<std::size_t>(t)];
  }
  for (int h : hits) EXPECT_EQ(h, 1);  // one centroid per true centre
}

TEST(KMeans, RecoversWellSeparatedClusters) {
  const RowMatrix truth = separated_centres();
  const RowMatrix points = clustered_points(truth, 400, 0.02, 1);
  for (KMeansMethod method : {KMeansMethod::kLloyd, KMeansMethod::kMiniBatch}) {
    SCOPED_TRACE(enum_to_string(kKMeansMethodNames, method));
    KMeansParams p;
    p.centroids = 8;
    p.init_samples = 1000;
    p.method = method;
    p.iterations = method == KMeansMethod::kLloyd ? 10 : 60;
    p.batch_size = 500;
    p.seed = 3;
    const KMeansResult r = kmeans(points, p);
    // The mean of 400 points with SD 0.02 is within ~0.001 per coordinate; mini-batch averages
    // the points it saw, a few thousand.
    expect_recovers(r.centroids, truth, 0.01);
    EXPECT_NEAR(r.cost.back(), 5 * 0.02 * 0.02, 0.0003);  // 5 coordinates of variance sd^2
  }
}

TEST(KMeans, LloydCostNeverRises) {
  const RowMatrix points = uniform_points(6000, 4, 2);
  for (KMeansInit init : {KMeansInit::kPlusPlus, KMeansInit::kRandom}) {
    KMeansParams p;
    p.centroids = 60;
    p.init = init;
    p.init_samples = 3000;
    p.iterations = 15;
    const KMeansResult r = kmeans(points, p);
    ASSERT_EQ(r.cost.size(), 16u);
    for (std::size_t t = 1; t < r.cost.size(); ++t) EXPECT_LE(r.cost[t], r.cost[t - 1] * (1 + 1e-6)) << "iteration " << t;
    EXPECT_LT(r.cost.back(), 0.9 * r.cost.front());
    EXPECT_DOUBLE_EQ(r.cost.back(), kmeans_cost(points, r.centroids));
  }
}

TEST(KMeans, SameBitsAtAnyThreadCount) {
  const RowMatrix points = uniform_points(9000, 6, 4);  // several 2048-point chunks
  for (KMeansMethod method : {KMeansMethod::kLloyd, KMeansMethod::kMiniBatch}) {
    KMeansParams p;
    p.centroids = 150;
    p.init_samples = 5000;
    p.method = method;
    p.iterations = 4;
    p.batch_size = 3000;
    std::vector<KMeansResult> results;
    for (int threads : {1, 2, 3}) {
      tbb::task_arena arena(threads);
      arena.execute([&] { results.push_back(kmeans(points, p)); });
    }
    for (std::size_t i = 1; i < results.size(); ++i) {
      EXPECT_TRUE(results[i].centroids == results[0].centroids);
      EXPECT_EQ(results[i].cost, results[0].cost);
    }
  }
}

TEST(KMeans, CvtCentroidsLieInTheUnitCubeAndFollowTheSeed) {
  KMeansParams p;
  p.centroids = 50;
  p.samples = 3000;
  p.init_samples = 3000;
  p.iterations = 3;
  const RowMatrix a = cvt_centroids(3, p).centroids;
  ASSERT_EQ(a.rows(), 50);
  ASSERT_EQ(a.cols(), 3);
  EXPECT_GE(a.minCoeff(), 0.0f);
  EXPECT_LE(a.maxCoeff(), 1.0f);
  EXPECT_TRUE(cvt_centroids(3, p).centroids == a);
  p.seed = 2;
  EXPECT_FALSE(cvt_centroids(3, p).centroids == a);
}

TEST(KMeans, RejectsBadParameters) {
  KMeansParams p;
  EXPECT_NO_THROW(p.validate());  // defaults are valid
  p.samples = 9000;
  EXPECT_INPUT_ERROR(p.validate(), "cvt.samples = 9000 is out of range: must be in [10000, 1000000000]");
  p = {};
  p.init_samples = 10;
  EXPECT_INPUT_ERROR(p.validate(), "cvt.init_samples = 10 is out of range: must be in [10000, 1000000000]");
  p = {};
  p.centroids = 0;
  EXPECT_INPUT_ERROR(p.validate(), "cvt.centroids = 0 is out of range: must be in [1, 10000000]");
}

}  // namespace
}  // namespace qdmeta
