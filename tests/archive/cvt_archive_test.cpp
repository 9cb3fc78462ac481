// Tests of src/qdmeta/archive/cvt_archive.{hpp,cpp}: cells by exact nearest centroid,
// strictly-better replacement, statistics with pyribs's meanings.
#include "qdmeta/archive/cvt_archive.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

CvtArchive square_archive(double qd_offset = 0.0) {
  RowMatrix centroids(4, 2);  // the corners of a square, one cell each
  centroids << 0.25f, 0.25f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f, 0.75f;
  return CvtArchive({1, qd_offset}, centroids);
}

TEST(CvtArchive, CellIsTheNearestCentroid) {
  const CvtArchive a = square_archive();
  const Real p0[2] = {0.1f, 0.2f}, p1[2] = {0.3f, 0.9f}, p2[2] = {0.6f, 0.4f}, p3[2] = {1.0f, 1.0f};
  EXPECT_EQ(a.index_of(p0), 0);
  EXPECT_EQ(a.index_of(p1), 1);
  EXPECT_EQ(a.index_of(p2), 2);
  EXPECT_EQ(a.index_of(p3), 3);
  const Real centre[2] = {0.5f, 0.5f};  // equidistant from all four: the lowest index
  EXPECT_EQ(a.index_of(centre), 0);
  EXPECT_EQ(a.cells(), 4);
  EXPECT_EQ(a.dimensions(), 2);
}

TEST(CvtArchive, ReplacesOnlyWithAStrictlyBetterObjective) {
  CvtArchive a = square_archive();
  const Real m[2] = {0.7f, 0.8f}, m2[2] = {0.8f, 0.7f};
  const Real s1 = 1.0f, s2 = 2.0f, s3 = 3.0f;
  EXPECT_EQ(a.add({&s1, 1}, 5.0f, m), AddStatus::kNew);
  EXPECT_EQ(a.add({&s2, 1}, 5.0f, m2), AddStatus::kNotAdded);  // equal: the incumbent stays
  EXPECT_EQ(*a.solution(3), 1.0f);
  EXPECT_EQ(a.add({&s2, 1}, 4.0f, m2), AddStatus::kNotAdded);
  EXPECT_EQ(a.add({&s3, 1}, 6.0f, m2), AddStatus::kImproved);
  EXPECT_EQ(*a.solution(3), 3.0f);
  EXPECT_EQ(a.objective(3), 6.0f);
  EXPECT_EQ(a.measures(3)[0], 0.8f);  // the descriptor of the new elite
  EXPECT_EQ(a.size(), 1);
  EXPECT_TRUE(a.occupied(3));
  EXPECT_FALSE(a.occupied(0));
}

TEST(CvtArchive, StatisticsUsePyribsMeanings) {
  CvtArchive a = square_archive(-10.0);
  EXPECT_EQ(a.stats(), ArchiveStats{});
  const Real s = 0.0f;
  const Real m0[2] = {0.2f, 0.2f}, m1[2] = {0.2f, 0.8f};
  a.add({&s, 1}, -2.0f, m0);
  a.add({&s, 1}, 4.0f, m1);
  const ArchiveStats st = a.stats();
  EXPECT_EQ(st.num_elites, 2);
  EXPECT_DOUBLE_EQ(st.coverage, 0.5);
  EXPECT_DOUBLE_EQ(st.obj_max, 4.0);
  EXPECT_DOUBLE_EQ(st.obj_mean, 1.0);
  EXPECT_DOUBLE_EQ(st.qd_score, (-2.0 + 10) + (4.0 + 10));
  EXPECT_DOUBLE_EQ(st.norm_qd_score, 22.0 / 4);
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.stats().num_elites, 0);
}

// Offspring at their parent's descriptor moved by steps from 0 to large, so that both the
// parent's neighbour list and the full search settle rows; lists of 1, 16 and all centroids.
TEST(CvtArchive, LocatingFromParentsGivesTheNearestCentroid) {
  Rng rng(31);
  RowMatrix centroids(500, 8);
  for (Index i = 0; i < centroids.size(); ++i) centroids.data()[i] = static_cast<Real>(rng.uniform());
  for (Index length : {1, 16, 500}) {
    SCOPED_TRACE(::testing::Message() << "lists of " << length);
    CvtArchive archive({1, 0.0, length}, centroids);
    EXPECT_EQ(archive.list_length(), length);
    const Real s = 0.0f;
    RowMatrix elites(400, 8);
    for (Index i = 0; i < elites.size(); ++i) elites.data()[i] = static_cast<Real>(rng.uniform());
    for (Index i = 0; i < 400; ++i) archive.add({&s, 1}, static_cast<Real>(rng.uniform()), {elites.row(i).data(), 8});
    Index searched = 0, total = 0;
    for (int round = 0; round < 3; ++round) {
      const Index count = 600;
      const std::vector<Index> filled = archive.filled_cells();
      RowMatrix offspring(count, 8);
      std::vector<Index> parents(static_cast<std::size_t>(count));
      for (Index r = 0; r < count; ++r) {
        const Index p = r % 7 == 0 ? -1 : filled[rng.below(filled.size())];
        parents[static_cast<std::size_t>(r)] = p;
        const double step = (r % 5) * 0.03;
        for (Index j = 0; j < 8; ++j) {
          const double base = p >= 0 ? archive.measures(p)[j] : rng.uniform();
          offspring(r, j) = static_cast<Real>(base + step * (rng.uniform() - 0.5));
        }
      }
      std::vector<Index> cells(static_cast<std::size_t>(count));
      searched += archive.locate(offspring.data(), count, parents.data(), cells.data());
      total += count;
      for (Index r = 0; r < count; ++r)
        ASSERT_EQ(cells[static_cast<std::size_t>(r)], nearest_centroid_naive(centroids, offspring.row(r).data()))
            << "row " << r;
      NeighbourLists lists;  // the offspring become elites: their lists serve the next round
      lists.resize(count, archive.list_length());
      for (Index r = 0; r < count; ++r) archive.neighbours_of(offspring.row(r).data(), -1, lists, r);
      for (Index r = 0; r < count; ++r)
        archive.add_to_cell(cells[static_cast<std::size_t>(r)], &s, 2.0f + static_cast<Real>(round), offspring.row(r).data(),
                            lists, r);
    }
    EXPECT_LT(searched, total * 6 / 10);  // lists settle the near offspring (the 1-entry list too, at step 0)
    EXPECT_GT(searched, total / 10);      // and the rows without a parent are searched
  }
}

// Ties and near-ties: centroids on a grid of quarters (exact arithmetic) with duplicates, and
// offspring exactly halfway between a parent's cell and a listed neighbour (equidistant: the
// lowest index must win), or nudged off the midpoint by about one float ulp. Lists are made in
// blocks (remake_lists), as CvtMapElites makes them, and must equal the lists one at a time.
TEST(CvtArchive, LocatingFromParentsIsExactOnVoronoiBoundaries) {
  Rng rng(37);
  const Index k = 400, d = 6, length = 24;
  RowMatrix centroids(k, d);
  for (Index i = 0; i < centroids.size(); ++i) centroids.data()[i] = static_cast<Real>(rng.below(5)) * 0.25f;
  for (Index i = 0; i < 20; ++i) centroids.row(k - 1 - i) = centroids.row(i * 7);  // exact duplicates, higher indices
  CvtArchive archive({1, 0.0, length}, centroids);
  const Real s = 0.0f;
  // Elites near every 3rd centroid, their lists made in blocks.
  RowMatrix elites(k / 3, d);
  for (Index i = 0; i < elites.rows(); ++i)
    for (Index j = 0; j < d; ++j) elites(i, j) = centroids(3 * i, j) + static_cast<Real>(0.05 * (rng.uniform() - 0.5));
  std::vector<Index> rows(static_cast<std::size_t>(elites.rows()));
  for (Index i = 0; i < elites.rows(); ++i) rows[static_cast<std::size_t>(i)] = i;
  NeighbourLists lists, one;
  lists.resize(elites.rows(), length);
  one.resize(1, length);
  archive.remake_lists(elites.data(), elites.rows(), rows.data(), lists);
  for (Index i = 0; i < elites.rows(); ++i) {
    archive.neighbours_of(elites.row(i).data(), -1, one, 0);
    ASSERT_TRUE(one.cells.row(0) == lists.cells.row(i)) << "elite " << i;
    ASSERT_TRUE(one.distances.row(0) == lists.distances.row(i)) << "elite " << i;
    ASSERT_EQ(one.outside[0], lists.outside[static_cast<std::size_t>(i)]) << "elite " << i;
  }
  for (Index i = 0; i < elites.rows(); ++i)
    archive.add_to_cell(archive.index_of(elites.row(i).data()), &s, 1.0f, elites.row(i).data(), lists, i);
  const std::vector<Index> filled = archive.filled_cells();
  const Index count = 3000;
  RowMatrix offspring(count, d);
  std::vector<Index> parents(static_cast<std::size_t>(count));
  Index ties = 0;
  for (Index r = 0; r < count; ++r) {
    const Index p = filled[rng.below(filled.size())];
    parents[static_cast<std::size_t>(r)] = p;
    const auto other = static_cast<Index>(rng.below(static_cast<std::uint64_t>(k)));
    offspring.row(r) = (centroids.row(p) + centroids.row(other)) / 2;  // exact: quarters halved
    if (r % 3 == 1) offspring(r, r % d) = std::nextafter(offspring(r, r % d), 2.0f);
    if (r % 3 == 2) offspring(r, r % d) = std::nextafter(offspring(r, r % d), -1.0f);
    const Index naive = nearest_centroid_naive(centroids, offspring.row(r).data());
    ties += squared_distance(offspring.row(r).data(), centroids.row(naive).data(), d) ==
            squared_distance(offspring.row(r).data(), centroids.row(p).data(), d) && naive != p;
  }
  std::vector<Index> cells(static_cast<std::size_t>(count));
  std::vector<std::uint8_t> settled(static_cast<std::size_t>(count));
  archive.locate(offspring.data(), count, parents.data(), cells.data(), settled.data());
  Index from_lists = 0;
  for (Index r = 0; r < count; ++r) {
    ASSERT_EQ(cells[static_cast<std::size_t>(r)], nearest_centroid_naive(centroids, offspring.row(r).data())) << "row " << r;
    from_lists += settled[static_cast<std::size_t>(r)];
  }
  EXPECT_GT(ties, count / 40);        // the case is there: exact ties won by a lower index
  EXPECT_GT(from_lists, count / 10);  // and the lists settle a good share of the rows
}

TEST(CvtArchive, RejectsBadParameters) {
  EXPECT_THROW(CvtArchive({0, 0.0}, RowMatrix::Zero(2, 2)), InputError);
  EXPECT_THROW(CvtArchive({1, 0.0}, RowMatrix(0, 2)), InputError);
}

}  // namespace
}  // namespace qdmeta
