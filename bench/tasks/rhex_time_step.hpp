#pragma once
// An RHex episode's settings at another time step, its settling rule kept in seconds (at most 5 s,
// 0.15 s quiet), for the comparison programs that change the step (rhex_turning, rhex_deaths,
// rhex_mujoco_settings).
#include <cmath>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"

namespace qdmeta::bench {

inline void set_time_step(rhex::EpisodeSettings& settings, double dt) {
  const double scale = settings.time_step / dt;
  settings.time_step = dt;
  settings.settle_steps = static_cast<int>(std::lround(settings.settle_steps * scale));
  settings.stable_steps = static_cast<int>(std::lround(settings.stable_steps * scale));
}

}  // namespace qdmeta::bench
