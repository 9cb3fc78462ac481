// Tests of src/qdmeta/emitters/ranking.{hpp,cpp}: each ranker's order on a hand-built batch.
#include "qdmeta/emitters/ranking.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "expect_input_error.hpp"

namespace qdmeta {
namespace {

// Five rows: statuses, improvement values and objectives chosen so that every ranker orders
// them differently.
struct HandBatch {
  RowMatrix solutions = RowMatrix::Zero(5, 1);
  std::vector<Real> objectives = {5.0f, 1.0f, 3.0f, 0.0f, 2.0f};
  std::vector<ThresholdOutcome> outcomes = {{AddStatus::kNotAdded, -1.0},
                                            {AddStatus::kImproved, 2.0},
                                            {AddStatus::kNew, 0.5},
                                            {AddStatus::kImproved, 3.0},
                                            {AddStatus::kNew, 4.0}};
  // Projections on the direction (1, -2): 1, -3, 2, 0, -1.
  RowMatrix measures = (RowMatrix(5, 2) << 1.0f, 0.0f, 1.0f, 2.0f, 0.0f, -1.0f, 2.0f, 1.0f, 1.0f, 1.0f).finished();
  EmitterResults results() const { return {solutions, objectives, measures, outcomes}; }
};

std::vector<int> ranked(EmitterRanker ranker, const EmitterResults& results) {
  const std::vector<double> direction = {1.0, -2.0};
  return rank_order(rank_keys(ranker, results, direction));
}

TEST(EmitterRanking, EachRankerOrdersAHandBuiltBatch) {
  const HandBatch b;
  // New cells (rows 4, 2) by improvement, then improved (3, 1), then the rest.
  EXPECT_EQ(ranked(EmitterRanker::kTwoStageImprovement, b.results()), (std::vector<int>{4, 2, 3, 1, 0}));
  EXPECT_EQ(ranked(EmitterRanker::kImprovement, b.results()), (std::vector<int>{4, 3, 1, 2, 0}));
  EXPECT_EQ(ranked(EmitterRanker::kObjective, b.results()), (std::vector<int>{0, 2, 4, 1, 3}));
  // Added rows (1..4) by objective, then row 0 despite its best objective.
  EXPECT_EQ(ranked(EmitterRanker::kTwoStageObjective, b.results()), (std::vector<int>{2, 4, 1, 3, 0}));
  EXPECT_EQ(ranked(EmitterRanker::kRandomDirection, b.results()), (std::vector<int>{2, 0, 3, 4, 1}));
  // New (2: 2, 4: -1), improved (3: 0, 1: -3), then row 0.
  EXPECT_EQ(ranked(EmitterRanker::kTwoStageRandomDirection, b.results()), (std::vector<int>{2, 4, 3, 1, 0}));
}

TEST(EmitterRanking, ADirectionOfTheWrongSizeIsRefused) {
  const HandBatch b;
  const std::vector<double> direction = {1.0, 0.0, 0.0};
  EXPECT_INPUT_ERROR(rank_keys(EmitterRanker::kRandomDirection, b.results(), direction),
                     "rank_keys: the random-direction ranker has a direction of 3 values for 2 measures");
}

TEST(EmitterRanking, TiesKeepAskOrder) {
  HandBatch b;
  b.outcomes = {{AddStatus::kImproved, 1.0},
                {AddStatus::kNew, 1.0},
                {AddStatus::kImproved, 1.0},
                {AddStatus::kNew, 1.0},
                {AddStatus::kNotAdded, 1.0}};
  EXPECT_EQ(ranked(EmitterRanker::kTwoStageImprovement, b.results()), (std::vector<int>{1, 3, 0, 2, 4}));
  EXPECT_EQ(ranked(EmitterRanker::kImprovement, b.results()), (std::vector<int>{0, 1, 2, 3, 4}));
}

TEST(EmitterRanking, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const auto& [ranker, name] : kEmitterRankerNames) {
    EXPECT_EQ(to_string(ranker), name);
    EXPECT_EQ(emitter_ranker_from_string(name), ranker);
  }
  EXPECT_INPUT_ERROR(emitter_ranker_from_string("imp"),
                     "emitter ranker = \"imp\" is not a valid choice: use one of \"improvement\", "
                     "\"two-stage-improvement\", \"objective\", \"two-stage-objective\", \"random-direction\", "
                     "\"two-stage-random-direction\"");
}

}  // namespace
}  // namespace qdmeta
