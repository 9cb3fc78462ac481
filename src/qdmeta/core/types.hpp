#pragma once
// The blocks of rows that algorithms, archives and evaluators exchange (core/scalars.hpp has
// Real and Index alone).
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "qdmeta/core/eigen.hpp"
#include "qdmeta/core/scalars.hpp"

namespace qdmeta {

// A block of rows (one solution per row), contiguous and row-major like a C array.
using RowMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1>;
static_assert(std::is_same_v<Index, Eigen::Index>);

}  // namespace qdmeta
