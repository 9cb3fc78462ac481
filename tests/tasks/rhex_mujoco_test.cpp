// Tests of the RHex task on MuJoCo (src/qdmeta/tasks/rhex/rhex_mjcf.*, rhex_mujoco_simulation.*):
// the MJCF model has the robot's parts and masses (that episodes give the same bits at any thread
// count is rhex_episode_test's, on each engine), the tripod gait walks forward about as far as on DART, every damage and
// course builds with the same legs as DART's, and the [task] engine key reaches the task and its
// meta-fitness. Short episodes where the property does not need 5 s.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <toml++/toml.h>

#include "own_temp_path.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#include "qdmeta/tasks/rhex/rhex_geometry.hpp"
#include "qdmeta/tasks/rhex/rhex_meta_fitness.hpp"
#include "qdmeta/tasks/rhex/rhex_mjcf.hpp"
#include "qdmeta/tasks/rhex/rhex_task.hpp"

namespace qdmeta {
namespace {

using rhex::DamageType;
using rhex::Engine;
using rhex::LegModel;
using rhex::ObstacleCourse;
using rhex::RhexEnvironment;

RhexParams params(Engine engine, double seconds) {
  RhexParams p;
  p.episode.engine = engine;
  p.episode.duration = seconds;
  return p;
}

// The model of `environment`, compiled by MuJoCo from a file (as the Python package would).
struct Model {
  explicit Model(const rhex::EpisodeSettings& s, const RhexEnvironment& environment = {}) {
    const auto path = test::own_temp_path("rhex_mujoco_test.xml");
    std::ofstream(path) << rhex::rhex_mjcf(s, environment);
    char error[1000] = "";
    m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
    EXPECT_NE(m, nullptr) << error;
  }
  ~Model() { mj_deleteModel(m); }
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
  mjModel* m = nullptr;
};

TEST(RhexMujoco, ModelHasTheRobotsPartsAndMass) {
  rhex::EpisodeSettings s;
  const double robot_mass = rhex::kBodyMass + 2 * rhex::kSpacerMass + rhex::kLegs * rhex::kPlates * rhex::kPlateMass;
  for (LegModel legs : {LegModel::kRigid, LegModel::kCompliant}) {
    s.legs = legs;
    const Model model(s);
    ASSERT_NE(model.m, nullptr);
    const int leg_bodies = legs == LegModel::kRigid ? 1 : rhex::kPlates;
    EXPECT_EQ(model.m->nbody, 2 + rhex::kLegs * leg_bodies);  // world, body, legs
    EXPECT_EQ(model.m->nv, 6 + rhex::kLegs * leg_bodies);     // free joint, hips, plate joints
    EXPECT_NEAR(mj_getTotalmass(model.m), robot_mass, 1e-9);
    EXPECT_EQ(model.m->opt.timestep, 0.005);
  }
  s.legs = LegModel::kRigid;
  EXPECT_EQ(Model(s, RhexEnvironment::damaged(DamageType::kLegRemoval, 2)).m->nbody, 7);
  EXPECT_EQ(Model(s, RhexEnvironment::damaged(DamageType::kBlockedHip, 2)).m->nv, 11);  // welded hip
  EXPECT_EQ(Model(s, RhexEnvironment::damaged(DamageType::kPassiveHip, 2)).m->nv, 12);
  EXPECT_NEAR(mj_getTotalmass(Model(s, RhexEnvironment::damaged(DamageType::kLegShortening, 2)).m),
              robot_mass - 3 * rhex::kPlateMass, 1e-9);
  // Rubble: a floor and 275 spheres, beside the robot's 3 body boxes and 48 plates.
  EXPECT_EQ(Model(s, RhexEnvironment::obstacle(ObstacleCourse::kRubble)).m->ngeom, 1 + 275 + 3 + 48);
}

// The solver options reach the compiled model; the faithful (default) ones are MuJoCo's defaults,
// named in the MJCF only where the model has always named them (integrator and cone).
void expect_options(const rhex::EpisodeSettings& s, mjtSolver solver, int iterations, double tolerance, mjtCone cone,
                    mjtIntegrator integrator, int noslip_iterations) {
  const Model model(s);
  ASSERT_NE(model.m, nullptr);
  EXPECT_EQ(model.m->opt.solver, solver);
  EXPECT_EQ(model.m->opt.iterations, iterations);
  EXPECT_EQ(model.m->opt.tolerance, tolerance);
  EXPECT_EQ(model.m->opt.cone, cone);
  EXPECT_EQ(model.m->opt.integrator, integrator);
  EXPECT_EQ(model.m->opt.noslip_iterations, noslip_iterations);
}

TEST(RhexMujoco, SolverOptionsReachTheModel) {
  rhex::EpisodeSettings s;
  const std::string faithful = rhex::rhex_mjcf(s, {});
  for (const char* attribute : {"solver=", "iterations=", "tolerance=", "noslip_iterations="})
    EXPECT_EQ(faithful.find(attribute), std::string::npos) << attribute;
  expect_options(s, mjSOL_NEWTON, 100, 1e-8, mjCONE_PYRAMIDAL, mjINT_EULER, 0);
  s.mujoco = {rhex::MujocoOptions::Solver::kCg, 20, 1e-5, true, true, 10};
  expect_options(s, mjSOL_CG, 20, 1e-5, mjCONE_ELLIPTIC, mjINT_IMPLICIT, 10);
  s.mujoco.solver = rhex::MujocoOptions::Solver::kPgs;
  expect_options(s, mjSOL_PGS, 20, 1e-5, mjCONE_ELLIPTIC, mjINT_IMPLICIT, 10);
}

// The compliant legs' plate joints carry DART's implicit spring in MuJoCo's parts (rhex_mjcf.cpp):
// armature h c + h^2 k and a velocity actuator of gain c + h k per joint, each leg 7 of them.
TEST(RhexMujoco, PlateJointsCarryDartsImplicitSpring) {
  rhex::EpisodeSettings s;
  s.legs = LegModel::kCompliant;
  const Model model(s, RhexEnvironment::damaged(DamageType::kLegShortening, 2));
  ASSERT_NE(model.m, nullptr);
  EXPECT_EQ(model.m->nu, 5 * 7 + 4);  // leg 2 has 5 plates: 4 joints
  const double h = 0.005;
  for (int leg : {0, 2})
    for (int k = 1; k < (leg == 2 ? 5 : 8); ++k) {
      const int j = mj_name2id(model.m, mjOBJ_JOINT, rhex::plate_joint_name(leg, k).c_str());
      ASSERT_GE(j, 0);
      const double stiffness = k == 1 || k == 7 ? 202672.0 : 152000.0;  // raised.skel
      EXPECT_EQ(model.m->jnt_stiffness[j], stiffness);
      EXPECT_DOUBLE_EQ(model.m->dof_armature[model.m->jnt_dofadr[j]], h * 0.1 + h * h * stiffness);
      EXPECT_EQ(model.m->dof_damping[model.m->jnt_dofadr[j]], 0.0);  // no second implicit term
      int gains = 0;
      for (int a = 0; a < model.m->nu; ++a)
        if (model.m->actuator_trnid[2 * a] == j) {
          ++gains;
          EXPECT_DOUBLE_EQ(model.m->actuator_gainprm[a * mjNGAIN], 0.1 + h * stiffness);
          EXPECT_DOUBLE_EQ(model.m->actuator_biasprm[a * mjNBIAS + 2], -(0.1 + h * stiffness));
        }
      EXPECT_EQ(gains, 1);
    }
}

// The compliant robot walks: no divergence (the spring alone diverges in 2 steps) and legs that
// bear the robot (an implicit joint damping alone let every robot fall over). DART's compliant
// tripod walks 3.77 m, MuJoCo's measured 3.33 m; the plates stay near their rest pose, so the
// robot walks about as its rigid twin on MuJoCo (3.39 m).
TEST(RhexMujoco, CompliantTripodWalksAsOnDart) {
  const auto genes = rhex::tripod_genes();
  RhexParams p = params(Engine::kMujoco, 5.0);
  const rhex::EpisodeResult rigid = RhexTask(p).episode(genes.data(), {});
  p.episode.legs = LegModel::kCompliant;
  const rhex::EpisodeResult mujoco = RhexTask(p).episode(genes.data(), {});
  p.episode.engine = Engine::kDart;
  const rhex::EpisodeResult dart = RhexTask(p).episode(genes.data(), {});
  ASSERT_FALSE(mujoco.dead);
  EXPECT_EQ(mujoco.walk_steps, 1000);
  EXPECT_EQ(mujoco.leg_bodies[0], 8);
  EXPECT_NEAR(mujoco.fitness, dart.fitness, 1.0);
  EXPECT_NEAR(mujoco.fitness, rigid.fitness, 0.3);
  EXPECT_LT(mujoco.max_tilt, 0.5);
  EXPECT_NEAR(mujoco.min_z, rigid.min_z, 0.01);  // the legs hold the body up as rigid ones do
}

// Measured (docs/fidelity.md, "MuJoCo"): 3.55 m on MuJoCo, 3.98 m on DART. A robot that sinks,
// slides or bounces (soft contacts, wrong friction, legs turned the wrong way) fails these bounds.
TEST(RhexMujoco, TripodWalksForwardAboutAsFarAsOnDart) {
  const auto genes = rhex::tripod_genes();
  const rhex::EpisodeResult dart = RhexTask(params(Engine::kDart, 5.0)).episode(genes.data(), {});
  const rhex::EpisodeResult mujoco = RhexTask(params(Engine::kMujoco, 5.0)).episode(genes.data(), {});
  ASSERT_FALSE(mujoco.dead);
  EXPECT_EQ(mujoco.walk_steps, 1000);
  EXPECT_GT(mujoco.fitness, 2.5);
  EXPECT_NEAR(mujoco.fitness, dart.fitness, 1.0);
  EXPECT_LT(std::abs(mujoco.final_pose.y), 0.25 * mujoco.fitness);
  EXPECT_LT(mujoco.max_tilt, 0.5);  // rad: no bouncing, no turning over
  for (int i = 0; i < rhex::kLegs; ++i) {
    EXPECT_GT(mujoco.hip_max[i] - mujoco.hip_min[i], 5 * 2 * 3.14159) << "leg " << i;
    EXPECT_GT(mujoco.counts.leg_contact[i], 0) << "leg " << i;  // every leg touched the floor
  }
}

// Zero hip torque: the C-legs roll under the robot's weight until the body rests on the floor,
// as on DART (measured: both 0.0695 m, half the body's height; 0.25 m backward on MuJoCo, 0.24 m
// on DART).
TEST(RhexMujoco, UncommandedRobotFoldsAsOnDart) {
  rhex::EpisodeSettings s;
  s.duration = 2.0;
  const rhex::EpisodeResult dart = rhex::run_uncommanded_episode(s, {});
  s.engine = Engine::kMujoco;
  const rhex::EpisodeResult mujoco = rhex::run_uncommanded_episode(s, {});
  ASSERT_FALSE(mujoco.dead);
  EXPECT_NEAR(mujoco.final_z, rhex::kBodyHeight / 2, 0.005);
  EXPECT_NEAR(mujoco.final_z, dart.final_z, 0.005);
  EXPECT_NEAR(mujoco.fitness, dart.fitness, 0.05);
  EXPECT_LT(std::abs(mujoco.final_pose.y), 0.02);
}

// The rubble course starts with stones inside the legs' reach. DART pushes a penetration out at
// 2 x depth per second (its error reduction); MuJoCo has that contact law too (rhex_mjcf.cpp), so
// neither throws the robot. With MuJoCo's earlier contact (time constant 2 steps) the body rose
// to 0.319 m in the first 0.5 s of the tripod gait (DART: 0.225, start 0.225; now 0.231).
TEST(RhexMujoco, StonesUnderTheStartingLegsDoNotThrowTheRobot) {
  RhexParams p = params(Engine::kMujoco, 0.5);
  p.episode.record_poses = true;
  const auto genes = rhex::tripod_genes();
  const rhex::EpisodeResult r = RhexTask(p).episode(genes.data(), RhexEnvironment::obstacle(ObstacleCourse::kRubble));
  double highest = 0.0;
  for (const rhex::PoseRecord& pose : r.poses)
    if (pose.time <= 0.5) highest = std::max(highest, pose.position[2]);
  EXPECT_LT(highest, rhex::kStartHeight + 0.01);
}

TEST(RhexMujoco, EveryDamageAndCourseBuildsTheLegsDartBuilds) {
  std::vector<RhexEnvironment> envs;
  for (DamageType d : {DamageType::kLegRemoval, DamageType::kLegShortening, DamageType::kBlockedHip, DamageType::kPassiveHip})
    envs.push_back(RhexEnvironment::damaged(d, 4));
  for (int c = 1; c <= 9; ++c) envs.push_back(RhexEnvironment::obstacle(static_cast<ObstacleCourse>(c)));
  const auto genes = rhex::tripod_genes();
  const RhexTask dart(params(Engine::kDart, 0.5)), mujoco(params(Engine::kMujoco, 0.5));
  for (const RhexEnvironment& env : envs) {
    const rhex::EpisodeResult d = dart.episode(genes.data(), env), m = mujoco.episode(genes.data(), env);
    EXPECT_EQ(m.leg_bodies, d.leg_bodies) << env.to_string();
    EXPECT_EQ(m.leg_plates, d.leg_plates) << env.to_string();
    EXPECT_TRUE(std::isfinite(m.fitness)) << env.to_string();
    EXPECT_NEAR(m.start_z, d.start_z, 1e-12) << env.to_string();
    // A blocked or removed hip never turns; a commanded one does.
    const bool blocked = env.damage == DamageType::kBlockedHip || env.damage == DamageType::kLegRemoval;
    if (env.damage != DamageType::kPassiveHip) {
      EXPECT_EQ(m.hip_max[4] - m.hip_min[4] > 0.5, !blocked) << env.to_string();
    }
  }
}

TEST(RhexMujoco, EngineKeyReachesTheTaskAndItsMetaFitness) {
  register_rhex_task();
  const std::string text =
      "algorithm = \"qd-meta\"\n[task]\nname = \"rhex\"\nengine = \"mujoco\"\n[meta_fitness]\nkind = \"obstacle\"\n";
  const BuiltRun built = build_run(toml::parse(text), "test", {});
  EXPECT_EQ(built.resolved["task"]["engine"].value_or<std::string>(""), "mujoco");
  // The meta-fitness's episodes run on MuJoCo: the same value as MuJoCo episodes run by hand.
  RhexParams p = params(Engine::kMujoco, 0.5);
  const std::vector<RhexEnvironment> envs{RhexEnvironment::obstacle(ObstacleCourse::kStairs),
                                          RhexEnvironment::damaged(DamageType::kPassiveHip, 0)};
  const RhexMetaFitness meta("rhex-test", {}, RhexTask(p), envs);
  RowMatrix elites(1, rhex::kGenes);
  const auto genes = rhex::tripod_genes();
  for (int j = 0; j < rhex::kGenes; ++j) elites(0, j) = genes[j];
  double expected = 0.0;
  for (const auto& e : envs) {
    const auto r = RhexTask(p).episode(genes.data(), e);
    expected += r.dead ? 0.0 : static_cast<double>(static_cast<Real>(r.fitness));
  }
  Rng rng(1);
  SerialEvaluator serial;
  EXPECT_DOUBLE_EQ(meta.evaluate(elites, rng, serial).value, expected / 2.0);
}

}  // namespace
}  // namespace qdmeta
