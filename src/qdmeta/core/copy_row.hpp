#pragma once
// Copies of short rows (a genotype of tens of genes) without a call into memmove: up to 32 floats
// as at most four fixed-size moves of 8 (or two of 4), the last ones overlapping the first, with
// no loop (GCC turns a copy loop back into a memmove call). At these lengths the call costs more
// than the copy, and the MAP-Elites loop makes one per offspring. Longer rows go to memcpy.
#include <cstring>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

// dst and src must not overlap.
inline void copy_row(const Real* __restrict src, Index n, Real* __restrict dst) {
  constexpr auto k8 = 8 * sizeof(Real);
  constexpr auto k4 = 4 * sizeof(Real);
  if (n > 32) {
    std::memcpy(dst, src, static_cast<std::size_t>(n) * sizeof(Real));
  } else if (n > 16) {
    std::memcpy(dst, src, k8);
    std::memcpy(dst + 8, src + 8, k8);
    std::memcpy(dst + n - 16, src + n - 16, k8);
    std::memcpy(dst + n - 8, src + n - 8, k8);
  } else if (n >= 8) {
    std::memcpy(dst, src, k8);
    std::memcpy(dst + n - 8, src + n - 8, k8);
  } else if (n >= 4) {
    std::memcpy(dst, src, k4);
    std::memcpy(dst + n - 4, src + n - 4, k4);
  } else if (n > 0) {
    dst[0] = src[0];
    if (n > 1) dst[1] = src[1];
    if (n > 2) dst[2] = src[2];
  }
}

}  // namespace qdmeta
