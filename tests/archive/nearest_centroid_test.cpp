// Tests of src/qdmeta/archive/nearest_centroid.{hpp,cpp}: the blocked-product search returns the
// centroid of the plain loop (lowest index on ties) at every size around the block edges, and
// the exact squared distance to it.
#include "qdmeta/archive/nearest_centroid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "qdmeta/archive/list_selection.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "random_block.hpp"

namespace qdmeta {
namespace {

void expect_finds_naive_nearest(const RowMatrix& centroids, const RowMatrix& points) {
  const NearestCentroid search(centroids);
  std::vector<Index> cells(static_cast<std::size_t>(points.rows()));
  std::vector<double> distances(cells.size());
  search.find(points.data(), points.rows(), cells.data(), distances.data());
  for (Index i = 0; i < points.rows(); ++i) {
    const Index expected = nearest_centroid_naive(centroids, points.row(i).data());
    ASSERT_EQ(cells[static_cast<std::size_t>(i)], expected) << "point " << i;
    ASSERT_EQ(distances[static_cast<std::size_t>(i)],
              squared_distance(points.row(i).data(), centroids.row(expected).data(), centroids.cols()));
    ASSERT_EQ(search.find(points.row(i).data()), expected) << "point " << i << " alone";
  }
}

TEST(NearestCentroid, MatchesThePlainLoopOnRandomData) {
  // Sizes straddle the 64-point and 512-centroid blocks; dimensions from 1 to 50.
  for (const auto& [k, d, n] : std::vector<std::tuple<Index, Index, Index>>{
           {1, 3, 5}, {7, 1, 300}, {511, 2, 200}, {512, 20, 129}, {513, 20, 65}, {2000, 20, 700}, {1500, 50, 100}}) {
    SCOPED_TRACE(::testing::Message() << k << " centroids, " << d << "-D, " << n << " points");
    const auto seed = static_cast<std::uint64_t>(k * 1000 + d);
    expect_finds_naive_nearest(random_block(k, d, seed), random_block(n, d, seed + 1));
  }
}

TEST(NearestCentroid, MatchesThePlainLoopForNearTiesAndFarPoints) {
  const RowMatrix centroids = random_block(1000, 20, 5);
  RowMatrix points(300, 20);
  Rng rng(6);
  for (Index i = 0; i < 100; ++i) {  // halfway between two centroids, nudged by 1 ulp-ish noise
    const Index a = static_cast<Index>(rng.below(1000)), b = static_cast<Index>(rng.below(1000));
    points.row(i) = (centroids.row(a) + centroids.row(b)) / 2;
    points(i, i % 20) += static_cast<Real>(1e-7 * (rng.uniform() - 0.5));
  }
  for (Index i = 100; i < 200; ++i)  // on top of a centroid, with tiny noise
    points.row(i) = centroids.row(static_cast<Index>(rng.below(1000))).array() + static_cast<Real>(1e-6 * rng.uniform());
  points.bottomRows(100) = random_block(100, 20, 7, -100.0, 100.0);  // far outside the cloud
  expect_finds_naive_nearest(centroids, points);
}

TEST(NearestCentroid, ExactTiesGoToTheLowestIndex) {
  RowMatrix line(2, 1);
  line << 0.25f, 0.75f;
  const Real middle = 0.5f;
  EXPECT_EQ(NearestCentroid(line).find(&middle), 0);

  // Duplicated centroids in different blocks: the first copy wins.
  RowMatrix centroids = random_block(1200, 20, 8);
  centroids.row(1100) = centroids.row(900);
  centroids.row(700) = centroids.row(900);
  const RowMatrix point = centroids.row(900);
  EXPECT_EQ(NearestCentroid(centroids).find(point.data()), 700);
  expect_finds_naive_nearest(centroids, random_block(200, 20, 9));
}

TEST(NearestCentroid, NeighbourListsAreSortedAndBoundTheirEntriesAndTheRest) {
  const Index k = 700, d = 20;
  const RowMatrix centroids = random_block(k, d, 41);
  const NearestCentroid search(centroids);
  const RowMatrix points = random_block(40, d, 42);
  for (Index length : {1, 30, 699, 700}) {
    std::vector<std::int32_t> cells(static_cast<std::size_t>(length));
    std::vector<float> distances(cells.size());
    for (Index i = 0; i < points.rows(); ++i) {
      double outside = 0.0;
      search.neighbours(points.row(i).data(), length, cells.data(), distances.data(), &outside);
      std::vector<bool> listed(static_cast<std::size_t>(k), false);
      for (Index j = 0; j < length; ++j) {
        const auto u = static_cast<std::size_t>(j);
        listed[static_cast<std::size_t>(cells[u])] = true;
        const double exact = std::sqrt(squared_distance(points.row(i).data(), centroids.row(cells[u]).data(), d));
        EXPECT_LE(distances[u], exact * (1 + 1e-7));  // a lower bound (rounded to float)
        EXPECT_GE(distances[u], exact - 1e-3);        // and not loose
        if (j > 0) {
          EXPECT_LE(distances[u - 1], distances[u]);
        }
      }
      EXPECT_EQ(cells[0], nearest_centroid_naive(centroids, points.row(i).data()));
      double nearest_unlisted = std::numeric_limits<double>::infinity();
      for (Index c = 0; c < k; ++c)
        if (!listed[static_cast<std::size_t>(c)])
          nearest_unlisted = std::min(nearest_unlisted, std::sqrt(squared_distance(points.row(i).data(), centroids.row(c).data(), d)));
      EXPECT_LE(outside, nearest_unlisted);
      EXPECT_GE(outside, nearest_unlisted - 1e-3);  // and not loose
      EXPECT_GE(outside, distances[static_cast<std::size_t>(length - 1)] - 1e-3);
    }
  }
}

// Lists are made kValueRows points at a time; each point's list must not depend on its block.
TEST(NearestCentroid, ListsMadeInBlocksEqualListsMadeOneAtATime) {
  const Index k = 1000, d = 20, n = 21, length = 64;  // 21 points: two blocks of 8 and one of 5
  const NearestCentroid search(random_block(k, d, 51));
  const RowMatrix points = random_block(n, d, 52);
  std::vector<std::int32_t> cells(static_cast<std::size_t>(n * length)), one_cells(static_cast<std::size_t>(length));
  std::vector<float> distances(cells.size()), one_distances(one_cells.size());
  std::vector<double> outside(static_cast<std::size_t>(n));
  search.neighbours(points.data(), n, length, cells.data(), distances.data(), outside.data());
  for (Index i = 0; i < n; ++i) {
    double one_outside = 0.0;
    search.neighbours(points.row(i).data(), length, one_cells.data(), one_distances.data(), &one_outside);
    for (Index j = 0; j < length; ++j) {
      const auto u = static_cast<std::size_t>(i * length + j);
      ASSERT_EQ(cells[u], one_cells[static_cast<std::size_t>(j)]) << "point " << i << " entry " << j;
      ASSERT_EQ(distances[u], one_distances[static_cast<std::size_t>(j)]) << "point " << i << " entry " << j;
    }
    EXPECT_EQ(outside[static_cast<std::size_t>(i)], one_outside) << "point " << i;
  }
}

TEST(NearestCentroid, ListSelectionPicksTheSmallestKeysAndSortsStably) {
  Rng rng(53);
  for (Index size : {2, 3, 17, 500, 3000}) {
    std::vector<std::uint64_t> keys;
    for (Index i = 0; i < size; ++i) {
      // Few distinct values (many ties), negative and positive, in index order.
      const auto value = static_cast<Real>(static_cast<double>(rng.below(7)) - 3.0) * 0.37f;
      keys.push_back(value_key(value, i));
    }
    for (Index i = 0; i < size; ++i) EXPECT_EQ(key_index(keys[static_cast<std::size_t>(i)]), i);
    std::vector<std::uint64_t> sorted = keys;
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i) EXPECT_LE(key_value(sorted[i - 1]), key_value(sorted[i]));
    for (Index count : {Index{1}, size / 2, size - 1}) {
      if (count < 1) continue;
      std::vector<std::uint64_t> chosen, scratch;
      const std::uint64_t next = select_smallest(keys, count, chosen, scratch);
      EXPECT_EQ(next, sorted[static_cast<std::size_t>(count)]) << size << " keys, " << count;
      std::vector<std::uint64_t> expected(sorted.begin(), sorted.begin() + count);
      std::sort(expected.begin(), expected.end(), [](auto a, auto b) { return key_index(a) < key_index(b); });
      EXPECT_EQ(chosen, expected) << size << " keys, " << count;  // in the keys' (index) order
    }
    std::vector<std::uint64_t> radix = keys, scratch;
    sort_by_value(radix, scratch);
    EXPECT_EQ(radix, sorted);  // stable: equal values stay in index order
  }
}

TEST(NearestCentroid, TheAnswerDoesNotDependOnHowRowsAreSplit) {
  const NearestCentroid search(random_block(800, 20, 10));
  const RowMatrix points = random_block(333, 20, 11);
  std::vector<Index> whole(333), split(333);
  search.find(points.data(), 333, whole.data());
  for (Index first = 0; first < 333; first += 50)
    search.find(points.row(first).data(), std::min<Index>(50, 333 - first), split.data() + first);
  EXPECT_EQ(whole, split);
}

TEST(NearestCentroid, RejectsBadInput) {
  EXPECT_THROW(NearestCentroid(RowMatrix(0, 3)), InputError);
  RowMatrix bad = random_block(4, 2, 12);
  bad(2, 1) = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_THROW(NearestCentroid{bad}, InputError);
  const NearestCentroid search(random_block(4, 2, 13));
  const Real nan_point[2] = {0.5f, std::numeric_limits<Real>::quiet_NaN()};
  EXPECT_THROW(search.find(nan_point), Error);
}

}  // namespace
}  // namespace qdmeta
