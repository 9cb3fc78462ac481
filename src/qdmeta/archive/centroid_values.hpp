#pragma once
// The float values ||c||^2 - 2 x.c of up to kValueRows points against every centroid, for
// neighbour lists: the centroids (as -2 C^T, row-major d x k) are streamed once per block of
// points instead of once per point, and each block of 16 centroids is accumulated in registers
// for all points of the block. Every value is the same sequence of operations (the norm, then
// one multiply-add per coordinate in index order) whatever the block, so a point's values do not
// depend on which points share its block.
#include "qdmeta/core/types.hpp"

namespace qdmeta {

inline constexpr Index kValueRows = 8;

// The layout centroid_values reads: -2 C^T in blocks of 16 centroids (block b, coordinate i:
// the values of centroids 16b .. 16b + 15 at (b * d + i) * 16), k padded with zero centroids to
// a multiple of 16 (kValueLanes).
inline constexpr Index kValueLanes = 16;
inline Index padded_centroids(Index k) { return (k + kValueLanes - 1) / kValueLanes * kValueLanes; }

// values[r * k + j] = norms[j] + sum_i points[r * d + i] * (-2 c_j)_i, the sum in index order,
// for r < rows (1 <= rows <= kValueRows) and j < k; k = padded_centroids(count), norms padded
// too.
void centroid_values(const Real* points, Index rows, const Real* blocked, const Real* norms, Index k, Index d,
                     Real* values);

}  // namespace qdmeta
