#pragma once
// The built-in algorithms' builders (experiment/algorithm_registry.hpp): "map-elites",
// "qd-meta", "cvt-map-elites" and "aurora", each reading its own config tables
// (docs/config.md). The library registers them before any registry lookup.
namespace qdmeta {
void register_builtin_algorithms();
}  // namespace qdmeta
