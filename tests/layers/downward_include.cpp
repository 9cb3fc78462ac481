// Compiled as a file of algorithms/ (tests/layers/CMakeLists.txt): its own folder and the layers
// below it, down to core/, are in reach, so this file builds.
#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/emitters/emitter.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
int downward_include_probe() { return 0; }
}  // namespace qdmeta
