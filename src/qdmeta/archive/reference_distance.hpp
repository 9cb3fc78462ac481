#pragma once
// The reference squared distance, inline for the bucket grid's inner loop. Its bits define the
// exact nearest centroid, so the product and the sum stay unfused: include this only from
// sources compiled with -ffp-contract=off (src/CMakeLists.txt), where every copy compiles to
// the same operations; everyone else calls squared_distance() (nearest_centroid.hpp).
#include "qdmeta/core/types.hpp"

namespace qdmeta {

inline double reference_squared_distance(const Real* a, const Real* b, Index dimensions) {
  double sum = 0.0;
  for (Index i = 0; i < dimensions; ++i) {
    const double d = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    sum += d * d;
  }
  return sum;
}

}  // namespace qdmeta
