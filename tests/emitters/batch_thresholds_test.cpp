// Tests of CellThresholds::offer_batch and add_with_thresholds(..., AddMode::kBatch): pyribs's
// add_mode "batch" (every row against the thresholds before the batch, one move per cell by the
// CMA-MAE paper's batch rule) against values worked by hand, against the rule applied k times
// to the mean, and against the single mode where a batch has one row per cell.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "expect_input_error.hpp"
#include "threshold_cases.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"
#include "qdmeta/emitters/thresholded_add.hpp"

namespace qdmeta {
namespace {

using test::expect_outcome;
using test::kInf;
using test::mae;

std::vector<ThresholdOutcome> offer_all(CellThresholds& t, const std::vector<Index>& cells, const std::vector<Real>& f,
                                        const std::vector<std::uint8_t>& valid = {}) {
  std::vector<ThresholdOutcome> outcomes(cells.size());
  t.offer_batch(cells, f, valid, outcomes);
  return outcomes;
}

TEST(BatchThresholds, ScoresEveryRowAgainstTheThresholdBeforeTheBatch) {
  // alpha = 0.5, threshold_min = 0; every value is exact in binary.
  CellThresholds t(4, mae(0.5, 0.0));
  auto o = offer_all(t, {1, 1, 2, 1, 0}, {4.0f, 2.0f, -1.0f, 6.0f, 1.0f});
  // Three rows into the empty cell 1: all new, each against threshold_min (one at a time, the
  // second would have been refused by t = 2 and the third scored 6 - 2).
  expect_outcome(o[0], AddStatus::kNew, 4.0);
  expect_outcome(o[1], AddStatus::kNew, 2.0);
  expect_outcome(o[3], AddStatus::kNew, 6.0);
  expect_outcome(o[2], AddStatus::kNotAdded, -1.0);  // below threshold_min: cell 2 stays unreached
  expect_outcome(o[4], AddStatus::kNew, 1.0);
  // k = 3, mean 4: t = 0.5^3 * 0 + (1 - 0.5^3) * 4 = 3.5; cell 0, k = 1: 0.5 * 0 + 0.5 * 1.
  EXPECT_EQ(t.threshold(1), 3.5);
  EXPECT_EQ(t.threshold(0), 0.5);
  EXPECT_EQ(t.threshold(2), 0.0);
  EXPECT_FALSE(t.reached(2));
  EXPECT_FALSE(t.reached(3));

  // Cell 1 now reached at 3.5: equal is not better; k = 2 of mean 6.5 give
  // t = 0.25 * 3.5 + 0.75 * 6.5 = 5.75.
  o = offer_all(t, {1, 1, 1, 1}, {3.5f, 5.5f, 7.5f, 1.0f});
  expect_outcome(o[0], AddStatus::kNotAdded, 0.0);
  expect_outcome(o[1], AddStatus::kImproved, 2.0);
  expect_outcome(o[2], AddStatus::kImproved, 4.0);
  expect_outcome(o[3], AddStatus::kNotAdded, -2.5);
  EXPECT_EQ(t.threshold(1), 5.75);
}

TEST(BatchThresholds, TiedRowsShareTheirOutcomeAndTheMean) {
  CellThresholds t(1, mae(0.5, 0.0));
  const auto o = offer_all(t, {0, 0}, {2.0f, 2.0f});
  expect_outcome(o[0], AddStatus::kNew, 2.0);
  expect_outcome(o[1], AddStatus::kNew, 2.0);
  EXPECT_EQ(t.threshold(0), 1.5);  // 0.25 * 0 + 0.75 * 2
}

// The rule is k offers of the rows' mean one at a time, in closed form: at alpha = 0.01 the two
// agree to rounding, for k = 2 and for a whole emitter batch of 36 in one cell.
TEST(BatchThresholds, ClosedFormIsKOffersOfTheMean) {
  for (const int k : {2, 7, 36}) {
    CellThresholds t(1, mae(0.01, -1.0));
    std::vector<Real> f;
    double sum = 0.0;
    for (int i = 0; i < k; ++i) {
      f.push_back(static_cast<Real>(1 + i % 5));
      sum += f.back();
    }
    offer_all(t, std::vector<Index>(static_cast<std::size_t>(k), 0), f);
    double reference = -1.0;
    for (int i = 0; i < k; ++i) reference = 0.99 * reference + 0.01 * (sum / k);
    EXPECT_NEAR(t.threshold(0), reference, 1e-14) << "k = " << k;
  }
  // Worked: k = 2 of 1 and 3 from 0 at alpha 0.01: 2 (1 - 0.99^2) = 0.0398.
  CellThresholds t(1, mae(0.01, 0.0));
  offer_all(t, {0, 0}, {1.0f, 3.0f});
  EXPECT_NEAR(t.threshold(0), 0.0398, 1e-16);
}

TEST(BatchThresholds, MinusInfinityTakesTheBestObjectiveAndScoresNewCellsAgainstZero) {
  CellThresholds t(2, mae(1.0, -kInf));
  auto o = offer_all(t, {0, 0, 0}, {2.0f, 5.0f, 3.0f});
  expect_outcome(o[0], AddStatus::kNew, 2.0);
  expect_outcome(o[1], AddStatus::kNew, 5.0);
  expect_outcome(o[2], AddStatus::kNew, 3.0);
  EXPECT_EQ(t.threshold(0), 5.0);
  o = offer_all(t, {0, 0, 0}, {4.0f, 7.0f, 6.0f});
  expect_outcome(o[0], AddStatus::kNotAdded, -1.0);
  expect_outcome(o[1], AddStatus::kImproved, 2.0);
  expect_outcome(o[2], AddStatus::kImproved, 1.0);
  EXPECT_EQ(t.threshold(0), 7.0);
  EXPECT_FALSE(t.reached(1));
}

// pyribs's rule with a finite threshold_min at learning rate 1: (1 - 1)^k = 0, so the threshold is
// the mean of the accepted objectives, not their best.
TEST(BatchThresholds, LearningRateOneWithAFloorTakesTheMean) {
  CellThresholds t(1, mae(1.0, 0.0));
  offer_all(t, {0, 0}, {2.0f, 4.0f});
  EXPECT_EQ(t.threshold(0), 3.0);
}

TEST(BatchThresholds, InvalidRowsEnterNoCellAndBadRowsChangeNothing) {
  CellThresholds t(2, mae(0.5, 0.0));
  const auto o = offer_all(t, {0, 99, 0}, {2.0f, std::numeric_limits<Real>::quiet_NaN(), 4.0f}, {1, 0, 1});
  expect_outcome(o[1], AddStatus::kNotAdded, -kInf);
  EXPECT_EQ(t.threshold(0), 2.25);  // 0.25 * 0 + 0.75 * 3
  std::vector<ThresholdOutcome> out(2);
  const std::vector<Index> cells = {1, 2};
  const std::vector<Real> f = {5.0f, 1.0f};
  EXPECT_INPUT_ERROR(t.offer_batch(cells, f, {}, out), "CellThresholds::offer_batch: cells[1] = 2 is outside [0, 2)");
  const std::vector<Real> nan = {5.0f, std::numeric_limits<Real>::infinity()};
  const std::vector<Index> ok = {1, 1};
  EXPECT_INPUT_ERROR(t.offer_batch(ok, nan, {}, out),
                     "CellThresholds::offer_batch: objectives[1] = inf is invalid: must be finite");
  EXPECT_FALSE(t.reached(1));  // the refused batches' first rows changed nothing
  std::vector<ThresholdOutcome> short_out(1);
  EXPECT_INPUT_ERROR(t.offer_batch(ok, f, {}, short_out),
                     "CellThresholds::offer_batch: 2 cells, 2 objectives, 0 valid flags and 1 outcome slots: give one "
                     "of each per row");
}

// With one row per cell the modes agree: the same statuses and improvements, and thresholds to
// rounding ((1 - alpha) t + (1 - (1 - alpha)) f against alpha f + (1 - alpha) t).
TEST(BatchThresholds, OneRowPerCellIsTheSingleModeToRounding) {
  CellThresholds single(50, mae(0.01, -0.5)), batch(50, mae(0.01, -0.5));
  Rng rng(5);
  for (int round = 0; round < 20; ++round) {
    std::vector<Index> cells;
    std::vector<Real> f;
    for (Index c = round % 2; c < 50; c += 2) {  // distinct cells
      cells.push_back(c);
      f.push_back(static_cast<Real>(rng.uniform() * 2.0 - 1.0));
    }
    const auto o = offer_all(batch, cells, f);
    for (std::size_t r = 0; r < cells.size(); ++r) {
      const ThresholdOutcome s = single.offer(cells[r], f[r]);
      EXPECT_EQ(o[r].status, s.status);
      EXPECT_NEAR(o[r].improvement, s.improvement, 1e-15);
    }
  }
  for (Index c = 0; c < 50; ++c) {
    EXPECT_EQ(batch.reached(c), single.reached(c));
    EXPECT_NEAR(batch.threshold(c), single.threshold(c), 1e-15);
  }
}

// Through the archive: the result archive keeps each cell's best row whatever the mode, and the
// outcomes are offer_batch's.
TEST(BatchThresholds, AddWithThresholdsInBatchModeKeepsTheBestElite) {
  GridArchiveParams gp;
  gp.bins = {2};
  gp.solution_size = 1;
  GridArchive archive(gp);
  CellThresholds thresholds(2, mae(0.5, 0.0));
  RowMatrix solutions(4, 1), measures(4, 1);
  solutions << 0.1f, 0.2f, 0.3f, 0.4f;
  measures << 0.2f, 0.3f, 0.8f, 0.4f;  // cells 0, 0, 1, 0
  const std::vector<Real> objectives = {4.0f, 6.0f, -2.0f, 2.0f};
  std::vector<ThresholdOutcome> outcomes(4);
  EXPECT_EQ(add_with_thresholds(archive, thresholds, EliteBatch{solutions, objectives, measures, {}, {}}, outcomes,
                                AddMode::kBatch),
            3);
  expect_outcome(outcomes[1], AddStatus::kNew, 6.0);
  expect_outcome(outcomes[3], AddStatus::kNew, 2.0);
  expect_outcome(outcomes[2], AddStatus::kNotAdded, -2.0);
  EXPECT_EQ(thresholds.threshold(0), 3.5);  // 0.125 * 0 + 0.875 * 4
  EXPECT_EQ(archive.objective(0), 6.0f);
  EXPECT_EQ(archive.solution(0)[0], 0.2f);
  EXPECT_EQ(to_string(AddMode::kBatch), "batch");
}

}  // namespace
}  // namespace qdmeta
