#pragma once
// The 0.2.0 place of plugin/algorithm_registry.hpp, kept for programs written then
// (CHANGELOG.md, "experiment/ split by job"); new code includes the new path.
#include "qdmeta/plugin/algorithm_registry.hpp"
