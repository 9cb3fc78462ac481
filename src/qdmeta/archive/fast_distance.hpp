#pragma once
// A fast squared distance for filtering, next to the reference squared_distance
// (nearest_centroid.hpp): the same double differences and squares, summed in eight independent
// lanes (which the compiler vectorises) instead of one chain in index order. Its bits may differ
// from the reference's in the last places, and with the instruction set, so it only ever decides
// which centroids get the reference check, never a cell: both sums of the same d non-negative
// terms lie within relative_error(d) of the exact real sum.
#include <cstddef>
#include <limits>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

inline double fast_squared_distance(const Real* a, const Real* b, Index dimensions) {
  constexpr int kLanes = 8;
  double lane[kLanes] = {};
  Index i = 0;
  for (; i + kLanes <= dimensions; i += kLanes)
    for (int j = 0; j < kLanes; ++j) {
      const double t = static_cast<double>(a[i + j]) - static_cast<double>(b[i + j]);
      lane[j] += t * t;
    }
  for (int j = 0; i + j < dimensions; ++j) {
    const double t = static_cast<double>(a[i + j]) - static_cast<double>(b[i + j]);
    lane[j] += t * t;
  }
  return ((lane[0] + lane[4]) + (lane[1] + lane[5])) + ((lane[2] + lane[6]) + (lane[3] + lane[7]));
}

// A bound, with a wide safety factor, on the relative distance of either sum (fast or
// reference) from the exact sum of the rounded differences' squares: d - 1 additions and d
// products (or fused multiply-adds), each within one unit roundoff.
inline double distance_relative_error(Index dimensions) {
  return 4.0 * static_cast<double>(dimensions + 2) * std::numeric_limits<double>::epsilon();
}

}  // namespace qdmeta
