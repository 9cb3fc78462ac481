#pragma once
// A (rows x cols) block of uniform values in [lo, hi) from `seed`: the random clouds of the
// centroid-search tests.
#include <cstdint>

#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

inline RowMatrix random_block(Index rows, Index cols, std::uint64_t seed, double lo = 0.0, double hi = 1.0) {
  Rng rng(seed);
  RowMatrix m(rows, cols);
  for (Index i = 0; i < m.size(); ++i) m.data()[i] = static_cast<Real>(rng.uniform(lo, hi));
  return m;
}

}  // namespace qdmeta
