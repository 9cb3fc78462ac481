// Compiled as a file of algorithms/ (tests/layers/CMakeLists.txt): run/ is a higher layer, so the
// build must refuse this include.
#include "qdmeta/run/run.hpp"
