// Compiled as a file of algorithms/ (tests/layers/CMakeLists.txt): tasks/ is in the same layer,
// so the build must refuse this include.
#include "qdmeta/tasks/rastrigin/rastrigin.hpp"
