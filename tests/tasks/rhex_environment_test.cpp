// Tests of the RHex damages and obstacle courses (src/qdmeta/tasks/rhex/rhex_{robot,terrain}.cpp):
// each changes the world as intended. The fast tripod gait (T = 0.33 s) reaches every obstacle.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta::rhex {
namespace {

using std::numbers::pi;


EpisodeResult walk(const RhexEnvironment& env, double seconds = 5.0, LegModel legs = LegModel::kRigid) {
  RhexParams p;
  p.episode.duration = seconds;
  p.episode.legs = legs;
  const auto g = tripod_genes(1.0f);
  return RhexTask(p).episode(g.data(), env);
}

const EpisodeResult& flat() {
  static const EpisodeResult r = walk({});
  return r;
}

TEST(RhexEnvironment, NamesAndValidation) {
  EXPECT_EQ(RhexEnvironment::damaged(DamageType::kBlockedHip, 3).to_string(), "blocked-hip:leg3");
  EXPECT_EQ(RhexEnvironment::obstacle(ObstacleCourse::kDownUpStairs).to_string(), "down-up-stairs");
  EXPECT_THROW(RhexEnvironment::damaged(DamageType::kPassiveHip, -1).validate(), InputError);
  EXPECT_THROW((RhexEnvironment{DamageType::kBlockedHip, 0, ObstacleCourse::kSlope}.validate()), InputError);
}

TEST(RhexDamage, IntactRobotWalksAndEveryLegTurns) {
  EXPECT_FALSE(flat().dead);
  EXPECT_GT(flat().fitness, 1.0);
  for (int leg = 0; leg < kLegs; ++leg) {
    EXPECT_EQ(flat().leg_bodies[leg], 1);
    EXPECT_EQ(flat().leg_plates[leg], 8);
    EXPECT_GT(flat().hip_max[leg] - flat().hip_min[leg], 10 * pi) << "leg " << leg;
    EXPECT_GT(flat().leg_swing[leg], 3.0) << "leg " << leg;  // passes through every angle
  }
}

TEST(RhexDamage, RemovedLegHasNoBody) {
  const EpisodeResult r = walk(RhexEnvironment::damaged(DamageType::kLegRemoval, 2), 1.0);
  EXPECT_EQ(r.leg_bodies[2], 0);
  EXPECT_EQ(r.leg_plates[2], 0);
  EXPECT_EQ(r.counts.leg_contact[2], 0);
  EXPECT_EQ(r.leg_bodies[0], 1);
  const EpisodeResult c = walk(RhexEnvironment::damaged(DamageType::kLegRemoval, 4), 1.0, LegModel::kCompliant);
  EXPECT_EQ(c.leg_bodies[4], 0);
  EXPECT_EQ(c.leg_bodies[3], 8);  // compliant legs: one body per plate
}

TEST(RhexDamage, ShortenedLegKeepsFivePlates) {
  const EpisodeResult r = walk(RhexEnvironment::damaged(DamageType::kLegShortening, 0), 1.0);
  EXPECT_EQ(r.leg_plates[0], 5);
  EXPECT_EQ(r.leg_plates[1], 8);
  EXPECT_GT(r.hip_max[0] - r.hip_min[0], 2 * pi);  // still driven
  const EpisodeResult c = walk(RhexEnvironment::damaged(DamageType::kLegShortening, 5), 1.0, LegModel::kCompliant);
  EXPECT_EQ(c.leg_bodies[5], 5);
}

TEST(RhexDamage, BlockedHipDoesNotMove) {
  const EpisodeResult r = walk(RhexEnvironment::damaged(DamageType::kBlockedHip, 1), 2.0);
  EXPECT_LT(r.leg_swing[1], 1e-9);
  EXPECT_GT(r.leg_swing[0], 3.0);
  EXPECT_NE(r.fitness, flat().fitness);
}

TEST(RhexDamage, PassiveHipSwingsButIsNotDriven) {
  const EpisodeResult r = walk(RhexEnvironment::damaged(DamageType::kPassiveHip, 4), 2.0);
  EXPECT_GT(r.leg_swing[4], 0.05);                   // moved by the body's motion and gravity
  EXPECT_LT(r.hip_max[4] - r.hip_min[4], 2 * pi);     // but never driven round
  EXPECT_GT(r.hip_max[3] - r.hip_min[3], 4 * pi);
}

TEST(RhexObstacles, StairsAndSlopeEndHigher) {
  for (ObstacleCourse course : {ObstacleCourse::kStairs, ObstacleCourse::kSlope}) {
    const EpisodeResult r = walk(RhexEnvironment::obstacle(course));
    EXPECT_GT(r.final_z, r.start_z + 0.1) << RhexEnvironment::obstacle(course).to_string();
    EXPECT_GT(r.final_z, flat().final_z + 0.1) << RhexEnvironment::obstacle(course).to_string();
  }
}

TEST(RhexObstacles, SphereLiftsTheRobot) {
  const EpisodeResult r = walk(RhexEnvironment::obstacle(ObstacleCourse::kSphere));
  EXPECT_GT(r.max_z, flat().max_z + 0.1);  // the sphere's top is 0.4 m above the floor at x = 2.6
}

TEST(RhexObstacles, DownUpStairsAndDitchGoDown) {
  for (ObstacleCourse course : {ObstacleCourse::kDownUpStairs, ObstacleCourse::kDitch}) {
    const EpisodeResult r = walk(RhexEnvironment::obstacle(course));
    EXPECT_LT(r.min_z, flat().min_z - 0.08) << RhexEnvironment::obstacle(course).to_string();
  }
}

// 3 cm bars hardly matter to 15 cm legs (measured: 3.92 m vs 3.85 m on flat, tilt 0.085 vs
// 0.069 rad), but the robot walks over them and they do perturb it.
TEST(RhexObstacles, ManyPipesAreCrossedAndPerturbTheWalk) {
  const EpisodeResult r = walk(RhexEnvironment::obstacle(ObstacleCourse::kManyPipes));
  EXPECT_GT(r.fitness, 1.4);  // over the first two bars (x = 0.4 and 1.4)
  EXPECT_GT(std::abs(r.fitness - flat().fitness) + std::abs(r.max_tilt - flat().max_tilt), 0.01);
}

TEST(RhexObstacles, RubbleAndPipesShakeOrBlockTheRobot) {
  for (ObstacleCourse course : {ObstacleCourse::kRubble, ObstacleCourse::kThickPipe, ObstacleCourse::kThinPipe}) {
    const EpisodeResult r = walk(RhexEnvironment::obstacle(course));
    const bool shaken = r.max_tilt > flat().max_tilt + 0.05;
    const bool slowed = r.dead || r.fitness < flat().fitness - 0.3;
    EXPECT_TRUE(shaken || slowed) << RhexEnvironment::obstacle(course).to_string() << ": tilt " << r.max_tilt
                                  << " vs " << flat().max_tilt << ", fitness " << r.fitness << " vs "
                                  << flat().fitness;
  }
}

}  // namespace
}  // namespace qdmeta::rhex
