// Tests of src/qdmeta/emitters/cell_thresholds.{hpp,cpp} and thresholded_add.hpp: CMA-MAE's
// threshold update against values worked by hand, alpha = 1 against MAP-Elites acceptance, the
// settings refused, and checkpoints.
#include "qdmeta/emitters/cell_thresholds.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "expect_input_error.hpp"
#include "threshold_cases.hpp"
#include "qdmeta/archive/cvt_archive.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/emitters/thresholded_add.hpp"

namespace qdmeta {
namespace {

using test::expect_outcome;
using test::kInf;
using test::mae;

// The thresholds key on the cells of the fixed-cell archives; AURORA's unstructured archive has none.
static_assert(CellIndexedArchive<GridArchive>);
static_assert(CellIndexedArchive<CvtArchive>);

TEST(CellThresholds, AnnealsByHandWorkedValues) {
  // alpha = 0.5, threshold_min = 0; every value is exact in binary.
  CellThresholds t(4, mae(0.5, 0.0));
  expect_outcome(t.offer(3, 4.0), AddStatus::kNew, 4.0);       // 4 - 0; t = 0.5 * 0 + 0.5 * 4 = 2
  EXPECT_EQ(t.threshold(3), 2.0);
  expect_outcome(t.offer(3, 3.0), AddStatus::kImproved, 1.0);  // 3 - 2; t = 0.5 * 2 + 0.5 * 3 = 2.5
  EXPECT_EQ(t.threshold(3), 2.5);
  expect_outcome(t.offer(3, 2.0), AddStatus::kNotAdded, -0.5);  // below: t unchanged
  expect_outcome(t.offer(3, 2.5), AddStatus::kNotAdded, 0.0);   // equal is not better
  EXPECT_EQ(t.threshold(3), 2.5);
  expect_outcome(t.offer(0, -1.0), AddStatus::kNotAdded, -1.0);  // below threshold_min: cell stays unreached
  EXPECT_FALSE(t.reached(0));
  EXPECT_EQ(t.threshold(0), 0.0);
  EXPECT_TRUE(t.reached(3));

  // alpha = 0.25 from threshold_min = -8: t = 0.75 * -8 + 0.25 * 8 = -4, then 0.75 * -4 + 0.25 * 0 = -3.
  CellThresholds q(1, mae(0.25, -8.0));
  expect_outcome(q.offer(0, 8.0), AddStatus::kNew, 16.0);
  EXPECT_EQ(q.threshold(0), -4.0);
  expect_outcome(q.offer(0, 0.0), AddStatus::kImproved, 4.0);  // a worse objective than the elite's still passes
  EXPECT_EQ(q.threshold(0), -3.0);
}

TEST(CellThresholds, AlphaZeroNeverMovesTheThreshold) {
  CellThresholds t(2, mae(0.0, 1.0));
  expect_outcome(t.offer(1, 5.0), AddStatus::kNew, 4.0);
  expect_outcome(t.offer(1, 2.0), AddStatus::kImproved, 1.0);
  expect_outcome(t.offer(1, 1.0), AddStatus::kNotAdded, 0.0);
  EXPECT_EQ(t.threshold(1), 1.0);
}

TEST(CellThresholds, MinusInfinityScoresNewCellsAgainstZero) {
  CellThresholds t(1, mae(1.0, -kInf));
  expect_outcome(t.offer(0, -7.0), AddStatus::kNew, -7.0);
  EXPECT_EQ(t.threshold(0), -7.0);
  expect_outcome(t.offer(0, -5.0), AddStatus::kImproved, 2.0);
  expect_outcome(t.offer(0, -6.0), AddStatus::kNotAdded, -1.0);
  EXPECT_EQ(t.threshold(0), -5.0);
}

TEST(CellThresholds, AlphaOneIsMapElitesAcceptanceOnARandomStream) {
  GridArchiveParams gp;
  gp.bins = {7, 5};
  gp.solution_size = 3;
  GridArchive archive(gp);
  CellThresholds thresholds(archive.cells(), mae(1.0, -kInf));
  GridArchive reference(gp);  // plain MAP-Elites, fed the same rows
  Rng rng(2024);
  constexpr Index kRows = 16;
  RowMatrix solutions(kRows, 3), measures(kRows, 2);
  std::vector<Real> objectives(kRows);
  std::vector<ThresholdOutcome> outcomes(kRows);
  std::vector<AddStatus> expected(kRows);
  Index new_cells = 0, improved = 0;
  for (int batch = 0; batch < 40; ++batch) {
    for (Index r = 0; r < kRows; ++r) {
      for (Index j = 0; j < 3; ++j) solutions(r, j) = static_cast<Real>(rng.uniform());
      for (Index j = 0; j < 2; ++j) measures(r, j) = static_cast<Real>(rng.uniform());
      objectives[static_cast<std::size_t>(r)] = static_cast<Real>(rng.uniform(-10.0, 10.0));
    }
    const EliteBatch b{solutions, objectives, measures, {}, {}};
    reference.add_batch(b, expected);
    add_with_thresholds(archive, thresholds, b, outcomes);
    for (Index r = 0; r < kRows; ++r) {
      const auto k = static_cast<std::size_t>(r);
      ASSERT_EQ(outcomes[k].status, expected[k]) << "batch " << batch << " row " << r;
      new_cells += expected[k] == AddStatus::kNew;
      improved += expected[k] == AddStatus::kImproved;
    }
  }
  EXPECT_EQ(new_cells, 35);  // every cell filled, and the stream exercised replacements
  EXPECT_GT(improved, 0);
  for (Index cell = 0; cell < archive.cells(); ++cell) {
    EXPECT_EQ(thresholds.threshold(cell), static_cast<double>(reference.objective(cell))) << cell;
    EXPECT_EQ(archive.objective(cell), reference.objective(cell)) << cell;
  }
}

TEST(CellThresholds, ResultArchiveKeepsTheBestWhileThresholdsAnneal) {
  GridArchiveParams gp;
  gp.bins = {1};
  gp.solution_size = 1;
  GridArchive archive(gp);
  CellThresholds thresholds(1, mae(0.5, 0.0));
  RowMatrix solutions(2, 1), measures(2, 1);
  solutions << 0.25f, 0.75f;
  measures << 0.5f, 0.5f;
  const std::vector<Real> objectives = {4.0f, 3.0f};
  std::vector<ThresholdOutcome> outcomes(2);
  EXPECT_EQ(add_with_thresholds(archive, thresholds, EliteBatch{solutions, objectives, measures, {}, {}}, outcomes), 2);
  EXPECT_EQ(outcomes[1].status, AddStatus::kImproved);  // 3 > t = 2
  EXPECT_EQ(archive.objective(0), 4.0f);                // the elite is still the best
  EXPECT_EQ(archive.solution(0)[0], 0.25f);
  EXPECT_EQ(thresholds.threshold(0), 2.5);
}

// A warm start from elites (QD-Meta's rebuilt maps): as offering each at learning rate 1, whatever
// alpha is; it never lowers a threshold, and an elite at or below threshold_min leaves its cell
// unreached. The annealing then goes on from there.
TEST(CellThresholds, RaiseToIsAnOfferAtLearningRateOne) {
  CellThresholds t(3, mae(0.5, -10.0));
  t.raise_to(0, -4.0);
  t.raise_to(1, -10.0);
  t.raise_to(2, -3.0);
  t.raise_to(2, -6.0);
  EXPECT_EQ(t.threshold(0), -4.0);
  EXPECT_TRUE(t.reached(0));
  EXPECT_EQ(t.threshold(1), -10.0);
  EXPECT_FALSE(t.reached(1));
  EXPECT_EQ(t.threshold(2), -3.0);
  const ThresholdOutcome o = t.offer(0, -2.0);  // improvement 2, then (1 - 0.5) -4 + 0.5 -2 = -3
  EXPECT_EQ(o.status, AddStatus::kImproved);
  EXPECT_EQ(o.improvement, 2.0);
  EXPECT_EQ(t.threshold(0), -3.0);
  EXPECT_INPUT_ERROR(t.raise_to(3, 0.0), "CellThresholds::raise_to: cell = 3 is outside [0, 3)");
}

TEST(CellThresholds, RefusesBadSettingsNamingTheKey) {
  EXPECT_INPUT_ERROR(mae(1.5, 0.0).validate(), "archive.learning_rate = 1.5 is out of range: must be in [0, 1]");
  EXPECT_INPUT_ERROR(mae(-0.1, 0.0).validate(), "archive.learning_rate = -0.1 is out of range: must be in [0, 1]");
  EXPECT_INPUT_ERROR(mae(0.5, -kInf).validate(),
                     "archive.threshold_min = -inf is out of range: must be finite, or -inf with learning_rate = 1 "
                     "(CMA-ME's)");
  EXPECT_NO_THROW(mae(1.0, -kInf).validate());
  EXPECT_INPUT_ERROR(mae(1.0, kInf).validate(),
                     "archive.threshold_min = inf is out of range: must be finite, or -inf with learning_rate = 1 "
                     "(CMA-ME's)");
  EXPECT_INPUT_ERROR(CellThresholds(0, mae(1.0, 0.0)), "CellThresholds cells = 0 is out of range: must be at least 1");
  CellThresholds t(2, mae(1.0, 0.0));
  EXPECT_INPUT_ERROR(t.offer(2, 1.0), "CellThresholds::offer: cell = 2 is outside [0, 2)");
  EXPECT_INPUT_ERROR(t.offer(0, kInf), "CellThresholds::offer: objective = inf is invalid: must be finite");
}

TEST(CellThresholds, CheckpointRoundTripsAndRefusesOtherParams) {
  CellThresholds t(5, mae(0.3, -1.0));
  Rng rng(7);
  for (int i = 0; i < 50; ++i) t.offer(static_cast<Index>(rng.uniform() * 5), rng.uniform(-2.0, 3.0));
  BinaryWriter out;
  t.save(out);
  CellThresholds back(5, mae(0.3, -1.0));
  BinaryReader in(out.bytes(), "test");
  back.load(in);
  in.finish();
  EXPECT_TRUE(back == t);
  CellThresholds other(5, mae(0.4, -1.0));
  BinaryReader again(out.bytes(), "test");
  EXPECT_INPUT_ERROR(other.load(again), "CellThresholds::load: the checkpoint has alpha = 0.3, threshold_min = -1; "
                                        "these thresholds have alpha = 0.4, threshold_min = -1");
}

}  // namespace
}  // namespace qdmeta
