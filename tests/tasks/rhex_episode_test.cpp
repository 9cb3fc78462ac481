// Tests of the RHex simulation (src/qdmeta/tasks/rhex/rhex_{robot,terrain,world,episode,task}.*):
// episodes are deterministic, base features have the right size and range, a hand-set tripod gait
// walks forward, and a robot commanded nothing stays where it landed. Episodes are shortened
// where the property does not need 5 s, to keep the suite fast.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {
namespace {

using rhex::RhexEnvironment;
constexpr double kBodyHeight = 0.139;  // docs/specification.md: body 0.54 x 0.39 x 0.139 m


RhexParams short_params(double seconds, RhexFeatures features = RhexFeatures::kTrajectory) {
  RhexParams p;
  p.episode.duration = seconds;
  p.features = features;
  return p;
}

RowMatrix random_genotypes(Index n, std::uint64_t seed) {
  RowMatrix g(n, rhex::kGenes);
  Rng rng(seed);
  for (Index i = 0; i < g.size(); ++i) g.data()[i] = static_cast<Real>(rng.uniform());
  return g;
}

TEST(RhexTask, SizesAndDefaults) {
  const RhexTask trajectory;
  EXPECT_EQ(trajectory.genotype_size(), 24);
  EXPECT_EQ(trajectory.base_feature_size(), 50);
  EXPECT_FALSE(trajectory.shareable());
  EXPECT_EQ(trajectory.qd_offset(), -1.0);
  EXPECT_EQ(RhexTask(short_params(1.0, RhexFeatures::kFeatureSets)).base_feature_size(), 15);
  EXPECT_NO_THROW(RhexParams{}.validate());
}

TEST(RhexTask, RejectsBadParams) {
  RhexParams p;
  p.episode.duration = 0.503;  // not a multiple of 10 steps
  EXPECT_THROW(RhexTask{p}, InputError);
  p = {};
  p.gene_step = 0.0;
  EXPECT_THROW(RhexTask{p}, InputError);
  p = {};
  p.environment = RhexEnvironment::damaged(rhex::DamageType::kLegRemoval, 6);
  EXPECT_THROW(RhexTask{p}, InputError);
}

// On each engine built (MuJoCo: one mjData per episode on a shared model; rigid and compliant legs).
TEST(RhexTask, EpisodesAreDeterministicAtAnyThreadCount) {
  std::vector<std::pair<rhex::Engine, rhex::LegModel>> models{{rhex::Engine::kDart, rhex::LegModel::kRigid}};
#ifdef QDMETA_TEST_MUJOCO
  models.emplace_back(rhex::Engine::kMujoco, rhex::LegModel::kRigid);
  models.emplace_back(rhex::Engine::kMujoco, rhex::LegModel::kCompliant);
#endif
  for (const auto& [engine, legs] : models) {
    RhexParams p = short_params(1.0);
    p.episode.engine = engine;
    p.episode.legs = legs;
    const Task task{RhexTask{p}};
    const RowMatrix genotypes = random_genotypes(4, 11);
    const GenotypeView view{genotypes.data(), genotypes.rows(), genotypes.cols()};
    EvaluationBatch a, b, c;
    a.resize(4, task.base_feature_size());
    b.resize(4, task.base_feature_size());
    c.resize(4, task.base_feature_size());
    task.evaluate(view, a.view());
    task.evaluate(view, b.view());
    make_thread_evaluator(2, 1)->evaluate(task, view, c.view());
    for (const EvaluationBatch* other : {&b, &c}) {
      EXPECT_EQ(std::memcmp(a.fitness.data(), other->fitness.data(), sizeof(Real) * 4), 0);
      EXPECT_EQ(std::memcmp(a.base_features.data(), other->base_features.data(), sizeof(Real) * 4 * 50), 0);
      EXPECT_EQ(a.valid, other->valid);
    }
  }
}

TEST(RhexTask, BaseFeaturesHaveTheRightSizeAndRange) {
  for (RhexFeatures features : {RhexFeatures::kTrajectory, RhexFeatures::kFeatureSets}) {
    const Task task{RhexTask{short_params(1.0, features)}};
    const RowMatrix genotypes = random_genotypes(3, 5);
    EvaluationBatch out;
    out.resize(3, task.base_feature_size());
    task.evaluate({genotypes.data(), 3, rhex::kGenes}, out.view());  // Task checks [0, 1] itself
    EXPECT_EQ(out.base_features.cols(), features == RhexFeatures::kTrajectory ? 50 : 15);
    for (Index i = 0; i < 3; ++i) {
      if (!out.valid[i]) continue;
      EXPECT_GE(out.base_features.row(i).minCoeff(), 0.0f);
      EXPECT_LE(out.base_features.row(i).maxCoeff(), 1.0f);
      EXPECT_GT(out.base_features.row(i).maxCoeff(), 0.0f);  // something was written
    }
  }
}

TEST(RhexEpisode, TripodGaitWalksForward) {
  const RhexTask task;  // the full 5 s episode
  const auto genes = rhex::tripod_genes();
  const rhex::EpisodeResult r = task.episode(genes.data(), {});
  ASSERT_FALSE(r.dead);
  EXPECT_EQ(r.walk_steps, 1000);
  EXPECT_GT(r.fitness, 1.0);  // measured: see bench/README.md
  EXPECT_LT(std::abs(r.final_pose.y), 0.5 * r.fitness);
  EXPECT_EQ(r.trajectory.size(), 11u);
  // Every hip turned several times (one turn per period of 0.665 s: ~7.5 turns in 5 s).
  for (int i = 0; i < rhex::kLegs; ++i) EXPECT_GT(r.hip_max[i] - r.hip_min[i], 5 * 2 * 3.14159) << "leg " << i;
  // Trajectory features say the same: forward x steps map above 0.5.
  std::array<Real, 50> b{};
  task.base_features(r, b.data());
  double forward = 0;
  for (int k = 1; k < 10; ++k) forward += b[5 * k] - 0.5;
  EXPECT_GT(forward, 0.0);
}

// Zero hip torque: the robot drops onto its legs, the unpowered C-legs roll under its weight and
// fold until the body rests on the floor (measured: 0.24 m backward, as the legs bulge backward,
// no sideways drift, body centre at 0.0695 m = half its height). It must stay far from the 3.27 m
// of the tripod gait.
TEST(RhexEpisode, UncommandedRobotStaysRoughlyInPlace) {
  const rhex::EpisodeResult r = rhex::run_uncommanded_episode({}, {});
  ASSERT_FALSE(r.dead);
  EXPECT_LT(std::abs(r.final_pose.x), 0.3);
  EXPECT_LT(std::abs(r.final_pose.y), 0.01);  // the robot is symmetric about its x-z plane
  EXPECT_LT(std::abs(r.final_pose.yaw), 0.01);
  EXPECT_NEAR(r.final_z, kBodyHeight / 2, 0.01);
  EXPECT_LT(r.settle_steps, 1000);
}

}  // namespace
}  // namespace qdmeta
