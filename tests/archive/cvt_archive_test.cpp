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
  EXPECT_EQ(a.add(&s1, 5.0f, m), AddStatus::kNew);
  EXPECT_EQ(a.add(&s2, 5.0f, m2), AddStatus::kNotAdded);  // equal: the incumbent stays
  EXPECT_EQ(*a.solution(3), 1.0f);
  EXPECT_EQ(a.add(&s2, 4.0f, m2), AddStatus::kNotAdded);
  EXPECT_EQ(a.add(&s3, 6.0f, m2), AddStatus::kImproved);
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
  a.add(&s, -2.0f, m0);
  a.add(&s, 4.0f, m1);
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

TEST(CvtArchive, LocatingFromParentsGivesTheNearestCentroid) {
  // 500 centroids in 8-D; elites at random points; offspring at the elites moved by steps from 0
  // (the parent's own descriptor) to large, so both the parent shortcut and the search are used.
  Rng rng(31);
  RowMatrix centroids(500, 8);
  for (Index i = 0; i < centroids.size(); ++i) centroids.data()[i] = static_cast<Real>(rng.uniform());
  CvtArchive archive({1, 0.0}, centroids);
  const Real s = 0.0f;
  RowMatrix elites(400, 8);
  for (Index i = 0; i < elites.size(); ++i) elites.data()[i] = static_cast<Real>(rng.uniform());
  for (Index i = 0; i < 400; ++i) archive.add(&s, static_cast<Real>(rng.uniform()), elites.row(i).data());
  const std::vector<Index>& filled = archive.filled_cells();
  for (int round = 0; round < 3; ++round) {
    const Index count = 600;
    RowMatrix offspring(count, 8);
    std::vector<Index> parents(static_cast<std::size_t>(count));
    for (Index r = 0; r < count; ++r) {
      const Index p = r % 7 == 0 ? -1 : filled[rng.below(filled.size())];
      parents[static_cast<std::size_t>(r)] = p;
      const double step = (r % 5) * 0.02;
      for (Index j = 0; j < 8; ++j) {
        const double base = p >= 0 ? archive.measures(p)[j] : rng.uniform();
        offspring(r, j) = static_cast<Real>(base + step * (rng.uniform() - 0.5));
      }
    }
    std::vector<Index> cells(static_cast<std::size_t>(count)), plain(cells.size());
    std::vector<double> bounds(cells.size()), plain_bounds(cells.size());
    archive.locate(offspring.data(), count, parents.data(), cells.data(), bounds.data());
    archive.locate(offspring.data(), count, nullptr, plain.data(), plain_bounds.data());
    EXPECT_EQ(cells, plain);
    for (Index r = 0; r < count; ++r) {
      const auto u = static_cast<std::size_t>(r);
      ASSERT_EQ(cells[u], nearest_centroid_naive(centroids, offspring.row(r).data())) << "row " << r;
      for (Index c = 0; c < 500; ++c) {
        if (c == cells[u]) continue;
        ASSERT_LE(bounds[u], std::sqrt(squared_distance(offspring.row(r).data(), centroids.row(c).data(), 8)));
      }
    }
    for (Index r = 0; r < count; ++r)  // the offspring become elites: their bounds feed the next round
      archive.add_to_cell(cells[static_cast<std::size_t>(r)], bounds[static_cast<std::size_t>(r)], &s, 2.0f + round,
                          offspring.row(r).data());
  }
}

TEST(CvtArchive, RejectsBadParameters) {
  EXPECT_THROW(CvtArchive({0, 0.0}, RowMatrix::Zero(2, 2)), InputError);
  EXPECT_THROW(CvtArchive({1, 0.0}, RowMatrix(0, 2)), InputError);
}

}  // namespace
}  // namespace qdmeta
