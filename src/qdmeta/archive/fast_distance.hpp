#pragma once
// A fast squared distance for filtering, next to the reference squared_distance
// (nearest_centroid.hpp): the same double differences and squares, summed in eight lanes of a
// vector and a scalar tail instead of one chain in index order. Its bits may differ
// from the reference's in the last places, and with the instruction set, so it only ever decides
// which centroids get the reference check, never a cell: both sums of the same d non-negative
// terms lie within distance_relative_error(d) of the exact real sum.
#include <cstddef>
#include <cstring>
#include <limits>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

namespace detail {
// Eight lanes in one vector (an AVX-512 register; split by the compiler on narrower machines),
// so that the partial sums stay in registers.
using Doubles = double __attribute__((vector_size(8 * sizeof(double))));
using Floats = Real __attribute__((vector_size(8 * sizeof(Real))));

// Always inlined: called once per walked entry, a call and the vector set-up cost as much as
// the arithmetic.
template <class A>
[[gnu::always_inline]] inline double lane_squared_distance(const A* a, const Real* b, Index dimensions) {
  Doubles acc = {};
  Index i = 0;
  for (; i + 8 <= dimensions; i += 8) {
    Floats fb;
    std::memcpy(&fb, b + i, sizeof fb);
    Doubles da;
    if constexpr (sizeof(A) == sizeof(double)) {
      std::memcpy(&da, a + i, sizeof da);
    } else {
      Floats fa;
      std::memcpy(&fa, a + i, sizeof fa);
      da = __builtin_convertvector(fa, Doubles);
    }
    const Doubles t = da - __builtin_convertvector(fb, Doubles);
    acc += t * t;
  }
  double tail = 0.0;
  if (i + 4 <= dimensions) {  // e.g. the last 4 of 20
    using Doubles4 = double __attribute__((vector_size(4 * sizeof(double))));
    Doubles4 quarter;
    for (int j = 0; j < 4; ++j) {
      const double t = static_cast<double>(a[i + j]) - static_cast<double>(b[i + j]);
      quarter[j] = t * t;
    }
    tail = (quarter[0] + quarter[2]) + (quarter[1] + quarter[3]);
    i += 4;
  }
  for (; i < dimensions; ++i) {
    const double t = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    tail += t * t;
  }
  return (((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]))) + tail;
}
}  // namespace detail

inline double fast_squared_distance(const Real* a, const Real* b, Index dimensions) {
  return detail::lane_squared_distance(a, b, dimensions);
}

// The same with `a` already in double (a point compared with many centroids): the same bits.
inline double fast_squared_distance(const double* a, const Real* b, Index dimensions) {
  return detail::lane_squared_distance(a, b, dimensions);
}

// A bound, with a wide safety factor, on the relative distance of either sum (fast or
// reference) from the exact sum of the rounded differences' squares: d - 1 additions and d
// products (or fused multiply-adds), each within one unit roundoff.
inline double distance_relative_error(Index dimensions) {
  return 4.0 * static_cast<double>(dimensions + 2) * std::numeric_limits<double>::epsilon();
}

}  // namespace qdmeta
