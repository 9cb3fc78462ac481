#pragma once
// One RHex episode (docs/specification.md, RHex): build the world, walk for `duration` seconds under the
// Buehler-clock controller, let the robot settle, and report what the task and the tests need.
// Engine-free header: DART and MuJoCo stay behind rhex_simulation.hpp.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/params.hpp"
#include "qdmeta/tasks/rhex/buehler_clock.hpp"
#include "qdmeta/tasks/rhex/rhex_environment.hpp"
#include "qdmeta/tasks/rhex/rhex_features.hpp"

namespace qdmeta::rhex {

// The physics engine of every episode: DART (the authors') or MuJoCo (docs/fidelity.md, "MuJoCo").
enum class Engine { kDart, kMujoco };
inline constexpr EnumNames<Engine, 2> kEngineNames{{{Engine::kDart, "dart"}, {Engine::kMujoco, "mujoco"}}};

enum class CollisionKind { kBullet, kDart, kFcl };
inline constexpr EnumNames<CollisionKind, 3> kCollisionKindNames{
    {{CollisionKind::kBullet, "bullet"}, {CollisionKind::kDart, "dart"}, {CollisionKind::kFcl, "fcl"}}};

enum class LcpSolver { kDantzig, kPgs };
inline constexpr EnumNames<LcpSolver, 2> kLcpSolverNames{{{LcpSolver::kDantzig, "dantzig"}, {LcpSolver::kPgs, "pgs"}}};

enum class LegModel {
  kRigid,     // each leg one rigid body carrying its 8 plates as collision shapes
  kCompliant  // the authors' model: 8 plate bodies joined by 7 stiff spring joints
};
inline constexpr EnumNames<LegModel, 2> kLegModelNames{{{LegModel::kRigid, "rigid"}, {LegModel::kCompliant, "compliant"}}};

// MuJoCo's solver and integrator options (engine = mujoco only). The defaults are MuJoCo's own
// and the faithful setting the engine cross-check measured (docs/fidelity.md, "RHex on MuJoCo");
// bench/tasks/rhex_mujoco_settings.cpp measures the others against it. Not a config key.
struct MujocoOptions {
  enum class Solver { kPgs, kCg, kNewton };
  Solver solver = Solver::kNewton;
  int iterations = 100;          // at most, per step
  double tolerance = 1e-8;       // the solver stops below this relative improvement
  bool elliptic_cone = false;    // false: the pyramidal cone (DART's friction box is nearer to it)
  bool implicit = false;         // MuJoCo's implicit-in-velocity integrator; false: semi-implicit Euler
  int noslip_iterations = 0;     // MuJoCo's no-slip pass after the solver; 0: none
  bool operator==(const MujocoOptions&) const = default;
};

struct EpisodeSettings {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr RealParam kTimeStep{"task", "time_step", 0.0, 0.1, Open::kLower,
      "simulation step and control cycle (s)"};
  static constexpr RealParam kEpisodeSeconds{"task", "episode_seconds", 0.0, 600.0, Open::kLower, "length of the walk"};
  static constexpr IntParam kSettleSteps{"task", "settle_steps", 0, 1'000'000,
      "most uncommanded steps after the walk; a robot not settled by then is dead (0: no settle phase)"};
  double time_step = 0.005;       // s, also the control cycle
  double duration = 5.0;          // s of walking
  int settle_steps = 1000;        // at most this many uncommanded steps after the walk
  int stable_steps = 30;          // settled after more than this many quiet steps in a row
  double stable_tolerance = 1e-4; // a step is quiet when the pose changes less than this
  double turnover_from = 2.0;     // s: from then on, a tilt of 90 degrees or more is death
  Engine engine = Engine::kDart;  // collision and lcp below are DART's own settings
  CollisionKind collision = CollisionKind::kBullet;
  LegModel legs = LegModel::kRigid;
  LcpSolver lcp = LcpSolver::kDantzig;  // DART's contact solver (Dantzig, PGS as its fallback)
  // Compliant legs: enforce the plate joints' limits [0, pi/64]. Their rest angle lies exactly on
  // the lower limit, so every plate joint is then a constraint row of every step's LCP.
  bool plate_joint_limits = true;
  MujocoOptions mujoco;           // MuJoCo's own solver settings
  bool record_poses = false;      // keep every step's body pose (gait export, tests)
  int steps() const { return static_cast<int>(duration / time_step + 0.5); }
  void validate() const;
};

// One recorded step (gait export): body position and XYZ Euler angles in the world, and each
// leg's rotation about y relative to the body (rad, in (-pi, pi]; 0 for a removed leg).
struct PoseRecord {
  double time = 0.0;
  std::array<double, 3> position{};
  std::array<double, 3> euler{};
  std::array<double, kLegs> legs{};
};

struct EpisodeResult {
  bool dead = false;
  bool turned_over = false;          // dead because the body tilted 90 degrees or more
  double fitness = 0.0;              // forward x displacement after settling (m)
  std::vector<RelativePose> trajectory;  // 11 samples, t = 0, duration / 10, ..., duration
  FeatureSetCounts counts;           // sampled every 10 ms
  RelativePose final_pose;           // after settling, relative to the start
  double start_z = 0.0;              // body height at the start (m)
  double final_z = 0.0;              // body height after settling (m)
  int walk_steps = 0;                // steps walked (fewer when it turned over)
  int settle_steps = 0;              // uncommanded steps until settled
  std::int64_t contacts = 0;         // contact points summed over the walk (cost diagnostics)
  std::array<int, kLegs> leg_bodies{};    // rigid bodies of each leg (0 when removed)
  std::array<int, kLegs> leg_plates{};    // collision plates of each leg
  std::array<double, kLegs> hip_min{};    // range of each hip joint angle over the walk (rad)
  std::array<double, kLegs> hip_max{};
  std::array<double, kLegs> leg_swing{};  // largest rotation of each leg relative to the body (rad,
                                          // from the bodies' transforms, wrapped to [0, pi])
  double min_z = 0.0, max_z = 0.0;   // body height range over the walk after its first second (m)
  double max_tilt = 0.0;             // largest angle of the body's z-axis from vertical (rad)
  std::vector<PoseRecord> poses;     // every step (walk and settle) when settings.record_poses
};

// The MJCF text MuJoCo's episodes of `settings` and `environment` step (qdmeta-rhex-gait --mjcf,
// for the mujoco Python package: tools/rhex_mujoco_episode.py); InputError in a build without
// MuJoCo.
std::string mujoco_model(const EpisodeSettings& settings, const RhexEnvironment& environment);

// Runs one episode in a fresh world (so the same input always gives the same bits).
EpisodeResult run_episode(const EpisodeSettings& settings, const GaitParams& gait, const RhexEnvironment& environment);

// The same episode with every hip commanded zero torque (a robot that does nothing).
EpisodeResult run_uncommanded_episode(const EpisodeSettings& settings, const RhexEnvironment& environment);

}  // namespace qdmeta::rhex
