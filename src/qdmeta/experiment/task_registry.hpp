#pragma once
// The old place of plugin/task_registry.hpp (qdmeta 0.1's tutorial included it from here); new code
// includes plugin/task_registry.hpp.
#include "qdmeta/plugin/task_registry.hpp"
