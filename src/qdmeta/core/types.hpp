#pragma once
// Shared numeric types. Genotypes, features and fitness are stored in float: the hot loops
// (evaluation, map rebuilds, nearest centroid) are bandwidth- and SIMD-bound, and float keeps
// 7 significant digits, far finer than any mutation step. Sums over archives use double.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

namespace qdmeta {

using Real = float;
// A block of rows (one solution per row), contiguous and row-major like a C array.
using RowMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
using Index = std::ptrdiff_t;

}  // namespace qdmeta
