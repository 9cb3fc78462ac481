#include "qdmeta/tasks/rhex/rhex_simulation.hpp"

#include "qdmeta/core/error.hpp"

namespace qdmeta::rhex {

std::unique_ptr<Simulation> make_simulation(const EpisodeSettings& settings, const RhexEnvironment& environment) {
  switch (settings.engine) {
    case Engine::kDart: return make_dart_simulation(settings, environment);
    case Engine::kMujoco:
#ifdef QDMETA_WITH_MUJOCO
      return make_mujoco_simulation(settings, environment);
#else
      throw InputError("task.engine = \"mujoco\": this qdmeta was built without MuJoCo (install libmujoco-dev, "
                       "scripts/install-deps.sh, and rebuild with QDMETA_WITH_MUJOCO=ON)");
#endif
  }
  throw InputError("unreachable RHex engine");
}

}  // namespace qdmeta::rhex
