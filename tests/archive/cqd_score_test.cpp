// The CQD score against sums worked by hand, its invariants, and its refusals.
#include "qdmeta/archive/cqd_score.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

// Two elites on a line: f = 10 at 0 and f = 4 at 1, objectives in [0, 10], dist_max 1.
const std::vector<double> kObjectives{10.0, 4.0};
const std::vector<double> kMeasures{0.0, 1.0};

CqdSettings three_penalties() {
  CqdSettings s;
  s.penalties = evenly_spaced_penalties(3);
  s.obj_min = 0.0;
  s.obj_max = 10.0;
  s.dist_max = 1.0;
  return s;
}

TEST(CqdScore, EvenlySpacedPenaltiesAreNumpysLinspaceFromZeroToOne) {
  EXPECT_EQ(evenly_spaced_penalties(1), (std::vector<double>{0.0}));
  EXPECT_EQ(evenly_spaced_penalties(2), (std::vector<double>{0.0, 1.0}));
  EXPECT_EQ(evenly_spaced_penalties(5), (std::vector<double>{0.0, 0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(evenly_spaced_penalties(3).back(), 1.0);
}

TEST(CqdScore, MatchesAHandWorkedSum) {
  // Normalised objectives 1.0 and 0.4. Targets 0, 1, 0.5:
  //   theta 0:   1 + 1 + 1                                   = 3
  //   theta 0.5: max(1, -0.1) + max(0.5, 0.4) + max(0.75, 0.15) = 2.25
  //   theta 1:   max(1, -0.6) + max(0, 0.4) + max(0.5, -0.1)    = 1.9
  // Second iteration, three targets at 0.25: 3 + 3 * 0.875 + 3 * 0.75 = 7.875.
  const std::vector<double> targets{0.0, 1.0, 0.5, 0.25, 0.25, 0.25};
  const CqdScore score = cqd_score(kObjectives, kMeasures, 1, targets, 2, three_penalties());
  ASSERT_EQ(score.scores.size(), 2u);
  EXPECT_NEAR(score.scores[0], 7.15, 1e-12);
  EXPECT_NEAR(score.scores[1], 7.875, 1e-12);
  EXPECT_NEAR(score.mean, (7.15 + 7.875) / 2, 1e-12);
}

TEST(CqdScore, ObjectivesAreNormalisedFromObjMin) {
  // Objectives in [-10, 10]: normalised 1.0 and 0.7; penalty 0 alone scores the best one per target.
  CqdSettings s = three_penalties();
  s.obj_min = -10.0;
  s.penalties = {0.0};
  const std::vector<double> targets{0.0, 1.0};
  EXPECT_NEAR(cqd_score(kObjectives, kMeasures, 1, targets, 1, s).mean, 2.0, 1e-12);
  s.penalties = {1.0};  // target 0: elite 1 (1.0); target 1: max(1 - 1, 0.7) = 0.7
  EXPECT_NEAR(cqd_score(kObjectives, kMeasures, 1, targets, 1, s).mean, 1.7, 1e-12);
}

TEST(CqdScore, DistanceIsThePNormOfTheOrderGiven) {
  // One elite of normalised objective 1 at (0, 0), one target at (3, 4), dist_max 10, penalty 1:
  // the score is 1 - d / 10.
  const std::vector<double> objective{1.0};
  const std::vector<double> origin{0.0, 0.0};
  const std::vector<double> target{3.0, 4.0};
  CqdSettings s;
  s.penalties = {1.0};
  s.dist_max = 10.0;
  const auto score_at = [&](double p) {
    s.dist_ord = p;
    return cqd_score(objective, origin, 2, target, 1, s).mean;
  };
  EXPECT_NEAR(score_at(2.0), 1.0 - 0.5, 1e-12);
  EXPECT_NEAR(score_at(1.0), 1.0 - 0.7, 1e-12);
  EXPECT_NEAR(score_at(std::numeric_limits<double>::infinity()), 1.0 - 0.4, 1e-12);
  EXPECT_NEAR(score_at(3.0), 1.0 - std::cbrt(91.0) / 10.0, 1e-12);
}

TEST(CqdScore, AnotherEliteNeverLowersTheScoreAndADominatedOneLeavesItUnchanged) {
  const std::vector<double> targets{0.0, 1.0, 0.5, 0.3, 0.9};
  const double before = cqd_score(kObjectives, kMeasures, 1, targets, 1, three_penalties()).mean;
  // A worse elite at the same point as another (f = 3 beside f = 4 at 1.0) changes no max.
  std::vector<double> objectives = kObjectives;
  std::vector<double> measures = kMeasures;
  objectives.push_back(3.0);
  measures.push_back(1.0);
  EXPECT_EQ(cqd_score(objectives, measures, 1, targets, 1, three_penalties()).mean, before);
  // A good elite near targets 0.5 and 0.3 raises it.
  objectives.push_back(9.0);
  measures.push_back(0.4);
  EXPECT_GT(cqd_score(objectives, measures, 1, targets, 1, three_penalties()).mean, before + 0.1);
}

void expect_refusal(const std::vector<double>& objectives, const std::vector<double>& measures,
                    const std::vector<double>& targets, std::size_t iterations, const CqdSettings& s,
                    const std::string& words) {
  try {
    (void)cqd_score(objectives, measures, 1, targets, iterations, s);
    ADD_FAILURE() << "accepted; expected a refusal naming " << words;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(CqdScore, RefusesEachBadArgumentNamingIt) {
  const std::vector<double> targets{0.0, 1.0};
  const CqdSettings good = three_penalties();
  expect_refusal({}, {}, targets, 1, good, "no elite");
  expect_refusal(kObjectives, {0.0}, targets, 1, good, "measures has 1 values");
  expect_refusal(kObjectives, kMeasures, {0.0}, 2, good, "target_points has 1 values");
  expect_refusal(kObjectives, kMeasures, targets, 0, good, "iterations");
  expect_refusal({10.0, std::nan("")}, kMeasures, targets, 1, good, "finite");
  expect_refusal(kObjectives, kMeasures, {0.0, INFINITY}, 1, good, "target_points must be finite");
  CqdSettings s = good;
  s.penalties = {};
  expect_refusal(kObjectives, kMeasures, targets, 1, s, "penalties is empty");
  s.penalties = {1.5};
  expect_refusal(kObjectives, kMeasures, targets, 1, s, "penalty 1.5 is outside [0, 1]");
  s = good;
  s.obj_max = s.obj_min;
  expect_refusal(kObjectives, kMeasures, targets, 1, s, "obj_max");
  s = good;
  s.dist_max = 0.0;
  expect_refusal(kObjectives, kMeasures, targets, 1, s, "dist_max");
  s = good;
  s.dist_ord = 0.5;
  expect_refusal(kObjectives, kMeasures, targets, 1, s, "dist_ord");
  EXPECT_THROW(evenly_spaced_penalties(0), InputError);
}

}  // namespace
}  // namespace qdmeta
