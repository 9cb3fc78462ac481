#pragma once
// The old place of plugin/config.hpp (qdmeta 0.1's tutorial included it from here); new code
// includes plugin/config.hpp.
#include "qdmeta/plugin/config.hpp"
