// One RHex episode: walk, watch for turnover, settle, measure (docs/specification.md, RHex).
#include "qdmeta/tasks/rhex/rhex_episode.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "qdmeta/tasks/rhex/rhex_geometry.hpp"
#include "qdmeta/tasks/rhex/rhex_simulation.hpp"

namespace qdmeta::rhex {

void EpisodeSettings::validate() const {
  require(kTimeStep, time_step);
  require(kEpisodeSeconds, duration);
  if (steps() % (kTrajectorySamples - 1) != 0)
    throw InputError(fmt::format("task.episode_seconds = {}: the episode must last a multiple of 10 time steps "
                                 "(it has {})", duration, steps()));
  require(kSettleSteps, settle_steps);
  require_range("task.stable_steps", stable_steps, 0, 1000000);
}

namespace {

constexpr int kFeatureEvery = 2;       // steps between feature-set samples (10 ms at 5 ms)

RelativePose relative_pose(const Eigen::Isometry3d& start, const Eigen::Isometry3d& now) {
  const Eigen::Vector3d d = now.translation() - start.translation();
  const Eigen::Vector3d euler = euler_xyz(start.linear().transpose() * now.linear());
  return {d.x(), d.y(), d.z(), euler.x(), euler.y(), euler.z()};
}


bool turned_over(const Eigen::Isometry3d& t) { return t.linear()(2, 2) <= 0.0; }  // body z-axis tilted >= 90 deg

class Episode {
 public:
  Episode(const EpisodeSettings& s, const RhexEnvironment& env) : s_(s), w_(make_simulation(s, env)) {
    result_.leg_bodies = w_->leg_bodies;
    result_.leg_plates = w_->leg_plates;
    for (int i = 0; i < kLegs; ++i) {
      const double q = w_->has_hip(i) ? w_->hip_angle(i) : 0.0;
      result_.hip_min[i] = result_.hip_max[i] = q;
    }
    for (int i = 0; i < kLegs; ++i) leg_start_[i] = leg_angle(i);
    start_ = w_->body_pose();
    result_.min_z = result_.max_z = start_.translation().z();
    result_.start_z = start_.translation().z();
    result_.trajectory.push_back(relative_pose(start_, start_));
  }

  EpisodeResult run(const GaitParams* gait) {
    const int steps = s_.steps();
    trajectory_every_ = std::max(1, steps / (kTrajectorySamples - 1));
    const int turnover_step = static_cast<int>(std::lround(s_.turnover_from / s_.time_step));
    for (int step = 0; step < steps; ++step) {
      command(gait, step * s_.time_step);
      w_->step();
      ++result_.walk_steps;
      result_.contacts += w_->contact_count();
      observe(step + 1);
      if (step + 1 >= turnover_step && turned_over(w_->body_pose())) {
        result_.dead = result_.turned_over = true;
        return finish();
      }
      if (w_->diverged()) {
        result_.dead = true;
        return finish();
      }
    }
    settle();
    return finish();
  }

 private:
  void command(const GaitParams* gait, double t) {
    for (int i = 0; i < kLegs; ++i) {
      if (!w_->actuated[i]) continue;
      double torque = 0.0;
      if (gait != nullptr) {
        const double measured = w_->hip_angle(i);
        const double target = unwrap_target(target_angle(*gait, i, t), measured, turns_[i]);
        torque = servos_[i].torque(target, measured, s_.time_step);
      }
      w_->set_hip_torque(i, torque);
    }
  }

  void observe(int step) {
    const Eigen::Isometry3d now = w_->body_pose();
    for (int i = 0; i < kLegs; ++i) {
      if (!w_->has_hip(i)) continue;
      const double q = w_->hip_angle(i);
      result_.hip_min[i] = std::min(result_.hip_min[i], q);
      result_.hip_max[i] = std::max(result_.hip_max[i], q);
    }
    for (int i = 0; i < kLegs; ++i) {
      if (w_->leg_bodies[i] == 0) continue;
      const double d = std::abs(std::remainder(leg_angle(i) - leg_start_[i], 2.0 * std::numbers::pi));
      result_.leg_swing[i] = std::max(result_.leg_swing[i], d);
    }
    if (step * s_.time_step >= 1.0) {
      if (!z_started_) result_.min_z = result_.max_z = now.translation().z();
      z_started_ = true;
      result_.min_z = std::min(result_.min_z, now.translation().z());
      result_.max_z = std::max(result_.max_z, now.translation().z());
    }
    result_.max_tilt = std::max(result_.max_tilt, std::acos(std::clamp(now.linear()(2, 2), -1.0, 1.0)));
    if (s_.record_poses) record(step, now);
    if (step % trajectory_every_ == 0) result_.trajectory.push_back(relative_pose(start_, now));
    if (step % kFeatureEvery == 0) {
      FeatureSetCounts& c = result_.counts;
      ++c.samples;
      const std::array<bool, kLegs> touching = w_->legs_touching();
      for (int i = 0; i < kLegs; ++i) c.leg_contact[i] += touching[i];
      c.add_orientation(relative_pose(start_, now));
      const Eigen::Vector3d v = w_->com_velocity();
      for (int j = 0; j < 3; ++j) c.velocity_sum[j] += v[j];
    }
  }

  void record(int step, const Eigen::Isometry3d& body) {
    PoseRecord p;
    p.time = step * s_.time_step;
    const Eigen::Vector3d euler = euler_xyz(body.linear());
    for (int j = 0; j < 3; ++j) {
      p.position[j] = body.translation()[j];
      p.euler[j] = euler[j];
    }
    for (int i = 0; i < kLegs; ++i) p.legs[i] = leg_angle(i);
    result_.poses.push_back(p);
  }

  // Rotation of leg i's first body about y relative to the robot body.
  double leg_angle(int i) const {
    if (w_->leg_bodies[i] == 0) return 0.0;
    const Eigen::Matrix3d r = w_->body_pose().linear().transpose() * w_->leg_rotation(i);
    return std::atan2(r(0, 2), r(0, 0));
  }

  // No commands until the pose has stayed still for more than `stable_steps` steps in a row.
  void settle() {
    for (int i = 0; i < kLegs; ++i)
      if (w_->actuated[i]) w_->set_hip_torque(i, 0.0);
    RelativePose last = relative_pose(start_, w_->body_pose());
    int quiet = 0;
    for (int step = 0; step < s_.settle_steps; ++step) {
      w_->step();
      ++result_.settle_steps;
      if (w_->diverged()) {
        result_.dead = true;
        return;
      }
      const Eigen::Isometry3d now_t = w_->body_pose();
      if (s_.record_poses) record(result_.walk_steps + step + 1, now_t);
      const RelativePose now = relative_pose(start_, now_t);
      const double change = std::sqrt(std::pow(now.x - last.x, 2) + std::pow(now.y - last.y, 2) +
                                      std::pow(now.z - last.z, 2) + std::pow(now.roll - last.roll, 2) +
                                      std::pow(now.pitch - last.pitch, 2) + std::pow(now.yaw - last.yaw, 2));
      last = now;
      quiet = change < s_.stable_tolerance ? quiet + 1 : 0;
      if (quiet > s_.stable_steps) return;
    }
    if (s_.settle_steps > 0) result_.dead = true;  // never settled
  }

  EpisodeResult finish() {
    const Eigen::Isometry3d now = w_->body_pose();
    result_.final_pose = relative_pose(start_, now);
    result_.final_z = now.translation().z();
    result_.fitness = result_.final_pose.x;
    return std::move(result_);
  }

  EpisodeSettings s_;
  std::unique_ptr<Simulation> w_;
  Eigen::Isometry3d start_;
  EpisodeResult result_;
  std::array<int, kLegs> turns_{};
  std::array<double, kLegs> leg_start_{};
  int trajectory_every_ = 1;
  bool z_started_ = false;
  std::array<PiServo, kLegs> servos_{};
};

}  // namespace

EpisodeResult run_episode(const EpisodeSettings& settings, const GaitParams& gait, const RhexEnvironment& environment) {
  return Episode(settings, environment).run(&gait);
}

EpisodeResult run_uncommanded_episode(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  return Episode(settings, environment).run(nullptr);
}

}  // namespace qdmeta::rhex
