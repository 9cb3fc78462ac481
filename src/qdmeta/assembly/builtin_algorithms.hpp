#pragma once
// The built-in algorithms' builders (plugin/algorithm_registry.hpp): "map-elites",
// "qd-meta", "cvt-map-elites", "aurora", "cma-me" and "cma-mae", each reading its own config tables
// (docs/config.md). ensure_core_plugins() registers them (assembly/core_plugins.hpp).
#include <string>
#include <utility>
#include <vector>

#include "qdmeta/plugin/algorithm_registry.hpp"

namespace qdmeta {
// In the order of the config's list of choices.
std::vector<std::pair<std::string, AlgorithmBuilder>> builtin_algorithms();
}  // namespace qdmeta
