// Tests of src/qdmeta/archive/centroid_grid.{hpp,cpp} and of NearestCentroid::find in 3
// dimensions or fewer: the bucket grid returns the plain loop's centroid (lowest index on exact
// ties) and its exact squared distance, on random clouds and on the cases a bucket grid can get
// wrong: exact ties across buckets, duplicated centroids, points on bucket edges and on
// centroids, flat and clustered clouds, points far outside the box.
#include "qdmeta/archive/centroid_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "random_block.hpp"

namespace qdmeta {
namespace {

// The rows of `m` in a random order, so that the lowest index of a tie is not the first in space.
RowMatrix shuffled(const RowMatrix& m, std::uint64_t seed) {
  std::vector<Index> order(static_cast<std::size_t>(m.rows()));
  std::iota(order.begin(), order.end(), Index{0});
  Rng rng(seed);
  for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[static_cast<std::size_t>(rng.below(i))]);
  RowMatrix out(m.rows(), m.cols());
  for (Index i = 0; i < m.rows(); ++i) out.row(i) = m.row(order[static_cast<std::size_t>(i)]);
  return out;
}

// Every point's answer from the grid, from NearestCentroid::find and from its blocked product is
// the plain loop's, with the plain loop's squared distance to the bit. Returns how many points
// had an exact tie for the nearest (so that tests can require ties to have been tried).
// `with_product`: also check find_by_product (the search used above 3-D); see the huge cloud below.
int expect_matches_naive(const RowMatrix& centroids, const RowMatrix& points, bool with_product = true) {
  const CentroidGrid grid(centroids);
  const NearestCentroid search(centroids);
  EXPECT_TRUE(search.has_grid());
  const Index n = points.rows(), d = centroids.cols();
  std::vector<Index> cells(static_cast<std::size_t>(n)), product(cells.size());
  std::vector<double> distances(cells.size());
  search.find(points.data(), n, cells.data(), distances.data());
  search.find_by_product(points.data(), n, product.data());
  int ties = 0;
  for (Index i = 0; i < n; ++i) {
    const Real* p = points.row(i).data();
    const Index expected = nearest_centroid_naive(centroids, p);
    const double expected_distance = squared_distance(p, centroids.row(expected).data(), d);
    double distance = -1.0;
    EXPECT_EQ(grid.find(p, &distance), expected) << "point " << i;
    EXPECT_EQ(distance, expected_distance) << "point " << i;
    EXPECT_EQ(cells[static_cast<std::size_t>(i)], expected) << "point " << i;
    EXPECT_EQ(distances[static_cast<std::size_t>(i)], expected_distance) << "point " << i;
    if (with_product) {
      EXPECT_EQ(product[static_cast<std::size_t>(i)], expected) << "point " << i;
    }
    for (Index c = expected + 1; c < centroids.rows(); ++c)
      if (squared_distance(p, centroids.row(c).data(), d) == expected_distance) {
        ++ties;
        break;
      }
    if (::testing::Test::HasFailure()) return ties;  // one point's report is enough
  }
  return ties;
}

TEST(CentroidGrid, MatchesThePlainLoopOnRandomClouds) {
  for (const auto& [k, d, n] : std::vector<std::tuple<Index, Index, Index>>{
           {1, 2, 50}, {2, 1, 200}, {7, 3, 300}, {100, 1, 500}, {500, 2, 1000}, {3000, 3, 1000}, {10'000, 2, 3000}}) {
    SCOPED_TRACE(::testing::Message() << k << " centroids, " << d << "-D");
    const auto seed = static_cast<std::uint64_t>(k * 10 + d);
    // Points inside the box, and in a box ten times larger (outside the grid on every side).
    expect_matches_naive(random_block(k, d, seed), random_block(n, d, seed + 1));
    expect_matches_naive(random_block(k, d, seed), random_block(n, d, seed + 2, -5.0, 5.0));
  }
}

TEST(CentroidGrid, ExactTiesGoToTheLowestIndexAcrossBuckets) {
  // Centroids on a lattice of step 1/8 in [0,1]^2, in random order: a point at a lattice square's
  // centre is equally far (exactly, in binary) from four centroids, a point on a lattice edge
  // from two, and the four usually sit in different buckets.
  RowMatrix lattice(81, 2);
  for (Index i = 0; i < 9; ++i)
    for (Index j = 0; j < 9; ++j) lattice.row(i * 9 + j) << static_cast<Real>(i) / 8, static_cast<Real>(j) / 8;
  const RowMatrix centroids = shuffled(lattice, 3);
  RowMatrix points(8 * 8 + 8 * 9 + 16 * 16, 2);
  Index row = 0;
  for (Index i = 0; i < 8; ++i)  // the squares' centres
    for (Index j = 0; j < 8; ++j) points.row(row++) << static_cast<Real>(2 * i + 1) / 16, static_cast<Real>(2 * j + 1) / 16;
  for (Index i = 0; i < 8; ++i)  // the middles of their edges
    for (Index j = 0; j < 9; ++j) points.row(row++) << static_cast<Real>(2 * i + 1) / 16, static_cast<Real>(j) / 8;
  for (Index i = 0; i < 16; ++i)  // and points a quarter of the way between (no ties)
    for (Index j = 0; j < 16; ++j) points.row(row++) << static_cast<Real>(2 * i + 1) / 32, static_cast<Real>(2 * j + 1) / 32;
  EXPECT_EQ(expect_matches_naive(centroids, points), 8 * 8 + 8 * 9);

  // The same in 1-D and 3-D.
  RowMatrix line(33, 1);
  for (Index i = 0; i < 33; ++i) line(i, 0) = static_cast<Real>(i) / 32;
  RowMatrix line_points(32, 1);
  for (Index i = 0; i < 32; ++i) line_points(i, 0) = static_cast<Real>(2 * i + 1) / 64;
  EXPECT_EQ(expect_matches_naive(shuffled(line, 4), line_points), 32);
  RowMatrix cube(125, 3);
  for (Index i = 0; i < 125; ++i)
    cube.row(i) << static_cast<Real>(i / 25) / 4, static_cast<Real>(i / 5 % 5) / 4, static_cast<Real>(i % 5) / 4;
  RowMatrix cube_points(64, 3);
  for (Index i = 0; i < 64; ++i)
    cube_points.row(i) << static_cast<Real>(2 * (i / 16) + 1) / 8, static_cast<Real>(2 * (i / 4 % 4) + 1) / 8,
        static_cast<Real>(2 * (i % 4) + 1) / 8;
  EXPECT_EQ(expect_matches_naive(shuffled(cube, 5), cube_points), 64);
}

TEST(CentroidGrid, ATieExactlyAtTheNextBucketsEdgeIsFound) {
  // Two buckets [0, 2) and [2, 4]: from 1, centroid 1 (at 0, in the point's bucket) and centroid
  // 0 (at 2, on the next bucket's edge) are both 1 away; the search must not stop at the edge.
  RowMatrix line(3, 1);
  line << 2.0f, 0.0f, 4.0f;
  const CentroidGrid grid(line);
  ASSERT_EQ(grid.buckets()[0], 2);
  const Real point = 1.0f;
  double distance = -1.0;
  EXPECT_EQ(grid.find(&point, &distance), 0);
  EXPECT_EQ(distance, 1.0);
}

TEST(CentroidGrid, DuplicatedCentroidsGiveTheFirstCopy) {
  RowMatrix centroids = random_block(2000, 2, 6);
  for (Index i = 0; i < 200; ++i) centroids.row(1999 - i) = centroids.row(i * 7);  // later copies
  centroids.row(300) = centroids.row(1500);                                       // an earlier copy
  RowMatrix points(400, 2);
  for (Index i = 0; i < 200; ++i) points.row(i) = centroids.row(i * 7);  // on the duplicated centroids
  points.row(200) = centroids.row(1500);
  points.bottomRows(199) = random_block(199, 2, 7);
  EXPECT_GE(expect_matches_naive(centroids, points), 200);
  double distance = -1.0;
  EXPECT_EQ(CentroidGrid(centroids).find(centroids.row(1500).data(), &distance), 300);
  EXPECT_EQ(distance, 0.0);
}

TEST(CentroidGrid, PointsOnBucketEdgesAndOnCentroids) {
  const RowMatrix centroids = random_block(5000, 2, 8);
  const CentroidGrid grid(centroids);
  // The buckets' edges along each axis, computed as the grid places them (low + b * width), and
  // their float neighbours on both sides, crossed with random coordinates on the other axis.
  const Real low[2] = {centroids.col(0).minCoeff(), centroids.col(1).minCoeff()};
  const Real high[2] = {centroids.col(0).maxCoeff(), centroids.col(1).maxCoeff()};
  std::vector<Real> rows;
  Rng rng(9);
  for (int axis = 0; axis < 2; ++axis) {
    const Index buckets = grid.buckets()[static_cast<std::size_t>(axis)];
    ASSERT_GT(buckets, 10);
    for (Index b = 0; b <= buckets; ++b) {
      const double width = (static_cast<double>(high[axis]) - low[axis]) / static_cast<double>(buckets);
      const auto at = static_cast<Real>(low[axis] + static_cast<double>(b) * width);
      for (Real x : {std::nextafter(at, -1.0f), at, std::nextafter(at, 2.0f)}) {
        Real p[2];
        p[axis] = x;
        p[1 - axis] = static_cast<Real>(rng.uniform());
        rows.insert(rows.end(), p, p + 2);
      }
    }
  }
  for (Index c = 0; c < 5000; c += 5) rows.insert(rows.end(), centroids.row(c).data(), centroids.row(c).data() + 2);
  const RowMatrix points = Eigen::Map<const RowMatrix>(rows.data(), static_cast<Index>(rows.size() / 2), 2);
  expect_matches_naive(centroids, points);
}

TEST(CentroidGrid, FlatClusteredAndExtremeClouds) {
  // On a line in 2-D and in 3-D (zero extent along the other axes), on a diagonal line, in two
  // tight clusters far apart, all at one point, a single centroid, huge and tiny coordinates.
  RowMatrix flat = random_block(3000, 2, 10);
  flat.col(1).setConstant(0.25f);
  RowMatrix flat3 = random_block(3000, 3, 11);
  flat3.col(0).setConstant(-2.0f);
  flat3.col(2).setConstant(7.0f);
  RowMatrix diagonal(2000, 2);
  const RowMatrix t = random_block(2000, 1, 12);
  diagonal << t, t;
  RowMatrix clusters = random_block(4000, 2, 13, 0.0, 1e-3);
  clusters.bottomRows(2000).array() += 100.0f;
  RowMatrix same(50, 3);
  same.setConstant(0.5f);
  const RowMatrix single = random_block(1, 2, 14);
  const RowMatrix huge = random_block(1000, 2, 15, -1e30, 1e30);
  const RowMatrix tiny = random_block(1000, 2, 16, 1.0, 1.0 + 1e-5);
  for (const RowMatrix* c :
       std::vector<const RowMatrix*>{&flat, &flat3, &diagonal, &clusters, &same, &single, &huge, &tiny}) {
    const Index d = c->cols();
    const double lo = c->minCoeff(), hi = c->maxCoeff(), pad = std::max(1.0, hi - lo);
    RowMatrix points(600, d);
    points.topRows(300) = random_block(300, d, 17, lo - 0.1 * pad, hi + 0.1 * pad);
    const Index on = std::min<Index>(200, c->rows());  // points on the centroids
    points.middleRows(300, 200) = c->topRows(on).replicate(200 / on + 1, 1).topRows(200);
    points.bottomRows(100) = random_block(100, d, 18, lo - 1e3 * pad, hi + 1e3 * pad);  // far outside
    SCOPED_TRACE(::testing::Message() << c->rows() << " x " << d << " cloud in [" << lo << ", " << hi << "]");
    // The blocked product of find_by_product, at coordinates of 1e30 and beyond, picked another
    // centroid than the plain loop in the sanitizer (Debug) build, not in Release: a limit of the
    // search above 3-D at magnitudes no measure reaches, not of the grid, which is checked here.
    expect_matches_naive(*c, points, /*with_product=*/c != &huge);
    // However flat the cloud, the buckets stay under 2^d per two centroids.
    const CentroidGrid grid(*c);
    Index total = 1;
    for (Index b : grid.buckets()) total *= b;
    EXPECT_LE(total, std::max<Index>(1, (Index{1} << d) * c->rows() / 2 + 1));
  }
}

TEST(CentroidGrid, NonFiniteInputs) {
  EXPECT_THROW(CentroidGrid(RowMatrix(0, 2)), InputError);
  EXPECT_THROW(CentroidGrid(random_block(10, 4, 19)), InputError);  // above the grid's dimensions
  RowMatrix bad = random_block(10, 2, 20);
  bad(3, 0) = std::numeric_limits<Real>::infinity();
  EXPECT_THROW(CentroidGrid{bad}, InputError);
  const CentroidGrid grid(random_block(10, 2, 21));
  double distance = 0.0;
  for (Real v : {std::numeric_limits<Real>::quiet_NaN(), std::numeric_limits<Real>::infinity(),
                 -std::numeric_limits<Real>::infinity()}) {
    const Real point[2] = {0.5f, v};
    EXPECT_EQ(grid.find(point, &distance), -1);
    const NearestCentroid search(random_block(10, 2, 21));
    EXPECT_THROW(search.find(point), Error);
  }
}

TEST(CentroidGrid, OnlyUpToThreeDimensions) {
  EXPECT_TRUE(NearestCentroid(random_block(10, 3, 22)).has_grid());
  EXPECT_FALSE(NearestCentroid(random_block(10, 4, 22)).has_grid());
}

}  // namespace
}  // namespace qdmeta
