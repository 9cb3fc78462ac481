#include "qdmeta/tasks/rhex/rhex_simulation.hpp"

#include "qdmeta/core/error.hpp"
#ifdef QDMETA_WITH_MUJOCO
#include "qdmeta/tasks/rhex/rhex_mjcf.hpp"
#endif

namespace qdmeta::rhex {
#ifndef QDMETA_WITH_MUJOCO
namespace {

[[noreturn]] void no_mujoco() {
  throw InputError("task.engine = \"mujoco\": this qdmeta was built without MuJoCo (install libmujoco-dev, "
                   "scripts/install-deps.sh, and rebuild with QDMETA_WITH_MUJOCO=ON)");
}

}  // namespace
#endif

std::unique_ptr<Simulation> make_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  switch (settings.engine) {
    case Engine::kDart: return make_dart_simulation(settings, environment);
    case Engine::kMujoco:
#ifdef QDMETA_WITH_MUJOCO
      return make_mujoco_simulation(settings, environment);
#else
      no_mujoco();
#endif
  }
  throw InputError("unreachable RHex engine");
}

std::string mujoco_model(const EpisodeSettings& settings, const RhexEnvironment& environment) {
#ifdef QDMETA_WITH_MUJOCO
  return rhex_mjcf(settings, environment);
#else
  no_mujoco();
#endif
}

}  // namespace qdmeta::rhex
