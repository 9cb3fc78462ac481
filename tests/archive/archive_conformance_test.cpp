// One behaviour suite over every cell-based archive (GridArchive, CvtArchive): each has four
// cells over [0, 1]^2, numbered alike (cell 2 * i + j holds the square i along measure 0, j along
// measure 1), so the same rows land in the same cells. The statistics of AURORA's unstructured
// archive, which shares the code, are checked at the end.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "qdmeta/archive/archive.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/archive/unstructured_archive.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

constexpr Index kGenes = 2;
constexpr double kOffset = -10.0;

struct GridMaker {
  static GridArchive make() {
    GridArchiveParams p;
    p.bins = {2, 2};
    p.solution_size = kGenes;
    p.qd_offset = kOffset;
    return GridArchive(p);
  }
};

struct CvtMaker {
  static CvtArchive make() {
    RowMatrix centroids(4, 2);
    centroids << 0.25f, 0.25f, 0.25f, 0.75f, 0.75f, 0.25f, 0.75f, 0.75f;
    return CvtArchive({kGenes, kOffset, 2}, centroids);
  }
};

template <class Maker>
class ArchiveConformance : public ::testing::Test {
 protected:
  using Archive = decltype(Maker::make());
  static_assert(EliteArchive<Archive>);
  Archive archive = Maker::make();
};

using CellArchives = ::testing::Types<GridMaker, CvtMaker>;
TYPED_TEST_SUITE(ArchiveConformance, CellArchives);

// Rows of a batch, owned.
struct Rows {
  RowMatrix solutions{0, kGenes};
  std::vector<Real> objectives;
  RowMatrix measures{0, 2};
  std::vector<std::uint8_t> valid;
  void push(Real x, Real y, Real objective, Real gene, bool is_valid = true) {
    const Index r = solutions.rows();
    solutions.conservativeResize(r + 1, kGenes);
    measures.conservativeResize(r + 1, 2);
    solutions.row(r) << gene, -gene;
    measures.row(r) << x, y;
    objectives.push_back(objective);
    valid.push_back(is_valid ? 1 : 0);
  }
  EliteBatch batch() const { return {solutions, objectives, measures, {}, valid}; }
};

// The cell of (x, y) in both archives.
Index cell_of(Real x, Real y) { return 2 * (x >= 0.5f ? 1 : 0) + (y >= 0.5f ? 1 : 0); }

template <class Archive>
std::string add_error(Archive& a, const EliteBatch& batch, std::span<AddStatus> status = {}) {
  try {
    a.add_batch(batch, status);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TYPED_TEST(ArchiveConformance, NewThenOnlyAStrictlyBetterObjectiveReplaces) {
  auto& a = this->archive;
  const Real s1[kGenes] = {1, 1}, s2[kGenes] = {2, 2}, s3[kGenes] = {3, 3};
  const Real m[2] = {0.2f, 0.7f}, m_same[2] = {0.3f, 0.6f};
  EXPECT_EQ(a.add(s1, 5.0f, m), AddStatus::kNew);
  EXPECT_EQ(a.add(s2, 5.0f, m_same), AddStatus::kNotAdded);  // equal: the incumbent stays
  EXPECT_EQ(a.add(s2, 4.0f, m_same), AddStatus::kNotAdded);
  EXPECT_EQ(a.solution(1)[0], 1.0f);
  EXPECT_EQ(a.add(s3, std::nextafter(5.0f, 6.0f), m_same), AddStatus::kImproved);
  EXPECT_EQ(a.solution(1)[0], 3.0f);
  EXPECT_EQ(a.measures(1)[0], 0.3f);
  EXPECT_EQ(a.objective(1), std::nextafter(5.0f, 6.0f));
  EXPECT_EQ(a.size(), 1);
  EXPECT_EQ(a.filled_cells(), std::vector<Index>{1});
}

TYPED_TEST(ArchiveConformance, InABatchTheFirstOfTiesKeepsTheCellAndInvalidRowsAreSkipped) {
  auto& a = this->archive;
  Rows rows;
  rows.push(0.1f, 0.1f, 5.0f, 1);                                    // new in cell 0
  rows.push(0.2f, 0.2f, 5.0f, 2);                                    // ties: not added
  rows.push(0.9f, 0.9f, 1.0f, 3);                                    // new in cell 3
  rows.push(0.3f, 0.3f, 9.0f, 4, false);                             // invalid: never added
  rows.push(std::numeric_limits<Real>::quiet_NaN(), 0.0f, 9.0f, 5, false);  // invalid, undefined measures
  rows.push(0.8f, 0.8f, 2.0f, 6);                                    // better: replaces in cell 3
  std::vector<AddStatus> status(6);
  EXPECT_EQ(a.add_batch(rows.batch(), status), 3);
  EXPECT_EQ(status, (std::vector<AddStatus>{AddStatus::kNew, AddStatus::kNotAdded, AddStatus::kNew,
                                            AddStatus::kNotAdded, AddStatus::kNotAdded, AddStatus::kImproved}));
  EXPECT_EQ(a.solution(0)[0], 1.0f);
  EXPECT_EQ(a.solution(3)[0], 6.0f);
  EXPECT_EQ(a.filled_cells(), (std::vector<Index>{0, 3}));
}

TYPED_TEST(ArchiveConformance, ABatchEqualsAddingItsRowsOneByOne) {
  auto batched = TypeParam::make();
  auto& one_by_one = this->archive;
  Rng rng(5);
  Rows rows;
  for (int r = 0; r < 300; ++r)
    rows.push(static_cast<Real>(rng.uniform()), static_cast<Real>(rng.uniform()),
              static_cast<Real>(std::floor(rng.uniform() * 20)), static_cast<Real>(r), rng.uniform() < 0.9);
  std::vector<AddStatus> status(300);
  batched.add_batch(rows.batch(), status);
  for (Index r = 0; r < 300; ++r) {
    const auto u = static_cast<std::size_t>(r);
    if (!rows.valid[u]) {
      EXPECT_EQ(status[u], AddStatus::kNotAdded);
      continue;
    }
    const Real* m = rows.measures.row(r).data();
    ASSERT_EQ(status[u], one_by_one.add({rows.solutions.row(r).data(), kGenes}, rows.objectives[u], {m, 2})) << r;
  }
  const EliteTable x = batched.elites(), y = one_by_one.elites();
  EXPECT_EQ(x.index, y.index);
  EXPECT_EQ(x.objective, y.objective);
  EXPECT_EQ(x.solutions, y.solutions);
  EXPECT_EQ(batched.filled_cells(), one_by_one.filled_cells());
}

TYPED_TEST(ArchiveConformance, NonFiniteObjectivesOrMeasuresAreRejectedWithTheRow) {
  auto& a = this->archive;
  const Real nan = std::numeric_limits<Real>::quiet_NaN(), inf = std::numeric_limits<Real>::infinity();
  for (const auto& [x, f, want] : std::vector<std::tuple<Real, Real, std::string>>{
           {nan, 1.0f, "row 1 of the batch has measure 0 = nan; measures must be finite"},
           {-inf, 1.0f, "row 1 of the batch has measure 0 = -inf; measures must be finite"},
           {0.5f, nan, "row 1 of the batch has objective nan; objectives must be finite"},
           {0.5f, inf, "row 1 of the batch has objective inf; objectives must be finite"}}) {
    Rows rows;
    rows.push(0.1f, 0.1f, 1.0f, 1);
    rows.push(x, 0.5f, f, 2);
    const std::string error = add_error(a, rows.batch());
    EXPECT_NE(error.find(want), std::string::npos) << error;
    EXPECT_TRUE(a.empty()) << "nothing is added from a rejected batch";
  }
}

// The batch's finiteness is decided by one pass over the bits (elite_batch.cpp): its edges, the
// largest float, the smallest subnormal and -0 accepted, every infinity and NaN (a negative NaN
// too) refused with its row and gene, and an invalid row never looked at.
TYPED_TEST(ArchiveConformance, EveryNonFiniteGeneIsRejectedAndEveryFiniteOneKept) {
  using limits = std::numeric_limits<Real>;
  const Real nan = limits::quiet_NaN(), inf = limits::infinity();
  for (const Real gene : {limits::max(), limits::denorm_min(), -0.0f, -limits::max()}) {
    auto a = TypeParam::make();
    Rows rows;
    rows.push(0.1f, 0.1f, 1.0f, gene);
    EXPECT_EQ(add_error(a, rows.batch()), "no error") << gene;
    EXPECT_EQ(a.elites().solutions(0, 0), gene);
  }
  for (const auto& [gene, printed] : std::vector<std::pair<Real, std::string>>{
           {inf, "inf"}, {-inf, "-inf"}, {nan, "nan"}, {-nan, "-nan"}}) {
    auto a = TypeParam::make();
    Rows rows;
    rows.push(0.1f, 0.1f, 1.0f, 0.5f);
    rows.push(0.6f, 0.1f, 1.0f, 0.5f, false);
    rows.solutions(1, 0) = nan;  // invalid: not looked at
    rows.push(0.6f, 0.6f, 1.0f, gene);
    const std::string want = "row 2 of the batch has solution value 0 = " + printed + "; solutions must be finite";
    const std::string error = add_error(a, rows.batch());
    EXPECT_NE(error.find(want), std::string::npos) << error;
    EXPECT_TRUE(a.empty()) << "nothing is added from a rejected batch";
  }
}

TYPED_TEST(ArchiveConformance, ShapeMismatchesAreRejected) {
  auto& a = this->archive;
  Rows rows;
  rows.push(0.1f, 0.1f, 1.0f, 1);
  rows.push(0.6f, 0.1f, 1.0f, 2);
  const RowMatrix three_measures = RowMatrix::Zero(2, 3);
  EliteBatch wide = rows.batch();
  wide.measures = three_measures;
  EXPECT_NE(add_error(a, wide).find("measures are 2 x 3 but 2 x 2 were expected"), std::string::npos)
      << add_error(a, wide);
  EliteBatch short_objectives = rows.batch();
  short_objectives.objectives = short_objectives.objectives.first(1);
  EXPECT_NE(add_error(a, short_objectives).find("1 objectives for 2 rows"), std::string::npos);
  EliteBatch short_valid = rows.batch();
  short_valid.valid = short_valid.valid.first(1);
  EXPECT_NE(add_error(a, short_valid).find("1 valid flags for 2 rows"), std::string::npos);
  std::vector<AddStatus> status(3);
  EXPECT_NE(add_error(a, rows.batch(), status).find("3 status entries given for 2 rows"), std::string::npos);
  const Real gene = 0;
  const Real m[2] = {0.1f, 0.1f};
  EXPECT_THROW(a.add({&gene, 1}, 1.0f, m), InputError);
  EXPECT_TRUE(a.empty());
}

TYPED_TEST(ArchiveConformance, StatisticsMatchAnIndependentCount) {
  auto& a = this->archive;
  EXPECT_EQ(a.stats(), ArchiveStats{});
  Rng rng(9);
  std::map<Index, double> best;  // cell -> best objective, from the cell rule above
  for (int t = 0; t < 7; ++t) {
    const auto x = static_cast<Real>(rng.uniform() * 0.5), y = static_cast<Real>(rng.uniform());
    const auto f = static_cast<Real>(rng.uniform(-5.0, 5.0));
    const Real s[kGenes] = {0, 0}, m[2] = {x, y};
    a.add(s, f, m);
    const Index c = cell_of(x, y);
    best[c] = best.contains(c) ? std::max(best[c], static_cast<double>(f)) : f;
  }
  double sum = 0, top = -1e300;
  for (const auto& [c, f] : best) {
    sum += f;
    top = std::max(top, f);
  }
  const auto n = static_cast<double>(best.size());
  const ArchiveStats s = a.stats();
  EXPECT_EQ(s.num_elites, static_cast<Index>(best.size()));
  EXPECT_DOUBLE_EQ(s.coverage, n / 4);
  EXPECT_NEAR(s.qd_score, sum - kOffset * n, 1e-9);
  EXPECT_NEAR(s.norm_qd_score, (sum - kOffset * n) / 4, 1e-9);
  EXPECT_DOUBLE_EQ(s.obj_max, top);
  EXPECT_NEAR(s.obj_mean, sum / n, 1e-9);
}

TYPED_TEST(ArchiveConformance, SaveLoadRoundTripsByteForByte) {
  auto& a = this->archive;
  Rows rows;
  rows.push(0.9f, 0.1f, 3.0f, 1);
  rows.push(0.1f, 0.1f, 2.0f, 2);
  rows.push(0.6f, 0.9f, -1.0f, 3);
  a.add_batch(rows.batch());
  BinaryWriter out;
  a.save(out);
  auto b = TypeParam::make();
  BinaryReader in(out.bytes(), "test");
  b.load(in);
  BinaryWriter again;
  b.save(again);
  EXPECT_EQ(again.bytes(), out.bytes());
  EXPECT_EQ(b.filled_cells(), (std::vector<Index>{2, 0, 3}));
  EXPECT_EQ(b.stats(), a.stats());
}

TYPED_TEST(ArchiveConformance, TheEliteTableIsSortedByCellAndComplete) {
  auto& a = this->archive;
  Rows rows;
  rows.push(0.9f, 0.9f, 3.0f, 1);
  rows.push(0.1f, 0.9f, 2.0f, 2);
  rows.push(0.6f, 0.1f, -1.0f, 3);
  a.add_batch(rows.batch());
  const EliteTable t = a.elites();
  EXPECT_EQ(t.index, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(t.objective, (std::vector<Real>{2.0f, -1.0f, 3.0f}));
  ASSERT_EQ(t.solutions.rows(), 3);
  EXPECT_EQ(t.solutions(0, 0), 2.0f);
  EXPECT_EQ(t.solutions(2, 1), -1.0f);
  EXPECT_EQ(t.measures(1, 0), 0.6f);
  EXPECT_EQ(t.measures(1, 1), 0.1f);
  EXPECT_EQ(t.base_features.cols(), 0);
}

TYPED_TEST(ArchiveConformance, ClearForgetsEveryElite) {
  auto& a = this->archive;
  Rows rows;
  rows.push(0.9f, 0.9f, 3.0f, 1);
  rows.push(0.1f, 0.9f, 2.0f, 2);
  a.add_batch(rows.batch());
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_TRUE(a.filled_cells().empty());
  for (Index c = 0; c < a.cells(); ++c) EXPECT_FALSE(a.occupied(c));
  EXPECT_EQ(a.stats(), ArchiveStats{});
  EXPECT_TRUE(a.elites().index.empty());
  const Real s[kGenes] = {0, 0}, m[2] = {0.9f, 0.9f};
  EXPECT_EQ(a.add(s, -100.0f, m), AddStatus::kNew);  // worse than the forgotten elite, new again
}

UnstructuredArchive three_member_archive() {
  UnstructuredArchiveParams p;
  p.measure_size = 2;
  p.solution_size = 1;
  p.target_size = 2;
  p.qd_offset = kOffset;
  UnstructuredArchive a(p);
  const std::vector<Real> objectives = {1.5f, -2.0f, 4.0f};
  for (std::size_t i = 0; i < objectives.size(); ++i) {
    const Real s = static_cast<Real>(i), d[2] = {static_cast<Real>(i) * 3, 0};
    EXPECT_EQ(a.add(&s, objectives[i], d, nullptr, 1.0), AddStatus::kNew);
  }
  return a;
}

// The behaviours of the suite above that AURORA's archive shares: save/load and clear.
TEST(UnstructuredArchiveConformance, SaveLoadRoundTripsByteForByte) {
  const UnstructuredArchive a = three_member_archive();
  BinaryWriter out;
  a.save(out);
  UnstructuredArchive b(a.params());
  BinaryReader in(out.bytes(), "test");
  b.load(in);
  BinaryWriter again;
  b.save(again);
  EXPECT_EQ(again.bytes(), out.bytes());
  EXPECT_EQ(b.stats(), a.stats());
  EXPECT_EQ(b.size(), 3);
}

TEST(UnstructuredArchiveConformance, ClearForgetsEveryMember) {
  UnstructuredArchive a = three_member_archive();
  a.clear();
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.stats(), ArchiveStats{});
  const Real s = 0, d[2] = {0, 0};
  EXPECT_EQ(a.add(&s, -100.0f, d, nullptr, 1.0), AddStatus::kNew);
}

// AURORA's archive counts coverage of the size it steers toward (capped at 1) with the same code.
TEST(UnstructuredArchiveConformance, StatisticsMatchAnIndependentCount) {
  EXPECT_EQ(UnstructuredArchive(three_member_archive().params()).stats(), ArchiveStats{});
  const ArchiveStats s = three_member_archive().stats();
  EXPECT_EQ(s.num_elites, 3);
  EXPECT_EQ(s.coverage, 1.0);  // 3 of a target of 2, capped
  EXPECT_DOUBLE_EQ(s.qd_score, 3.5 + 30.0);
  EXPECT_DOUBLE_EQ(s.norm_qd_score, 33.5 / 2);
  EXPECT_DOUBLE_EQ(s.obj_max, 4.0);
  EXPECT_DOUBLE_EQ(s.obj_mean, 3.5 / 3);
}

}  // namespace
}  // namespace qdmeta
