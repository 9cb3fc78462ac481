#pragma once
// The scalar types every layer shares, without Eigen: a task's file needs only these and the
// views of core/task.hpp. Genotypes, features and fitness are stored in float: the hot loops
// (evaluation, map rebuilds, nearest centroid) are bandwidth- and SIMD-bound, and float keeps
// 7 significant digits, far finer than any mutation step. Sums over archives use double.
#include <cstddef>

namespace qdmeta {

using Real = float;
using Index = std::ptrdiff_t;  // Eigen's index type too

}  // namespace qdmeta
