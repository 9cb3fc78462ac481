#pragma once
// The MJCF (MuJoCo's XML model) of one RHex episode, written from the same geometry as DART's
// robot (rhex_geometry.hpp) and the same course shapes (rhex_course.hpp): docs/fidelity.md,
// "MuJoCo". Only elements that MuJoCo 2.2 and 3.x both read, so that the Python `mujoco` package
// loads the same text. Internal to qdmeta_rhex_mujoco (needs no MuJoCo header itself).
#include <string>

#include "qdmeta/tasks/rhex/rhex_episode.hpp"

namespace qdmeta::rhex {

std::string rhex_mjcf(const EpisodeSettings& settings, const RhexEnvironment& environment);

// Names in the model, for the engine to find its bodies and joints.
std::string leg_body_name(int leg, int plate);  // plate 0: the body the hip drives
std::string hip_joint_name(int leg);
std::string plate_joint_name(int leg, int plate);  // compliant legs: plate >= 1, between plates plate - 1 and plate

}  // namespace qdmeta::rhex
