#pragma once
// Exact nearest-centroid search in 1 to 3 dimensions: a uniform grid of buckets over the
// centroids' bounding box, about two centroids to a bucket. A query visits the buckets in rings
// around its own (ring r: the buckets r steps away along some axis) and stops once every bucket
// left lies farther than the best centroid found, so it reads a few dozen centroids where the
// blocked product (nearest_centroid.hpp) reads all of them; above 3 dimensions the rings grow
// too fast to pay. Distances are the reference squared_distance and ties go to the lowest
// index: the answer is the plain loop's (nearest_centroid_naive). Points far outside the box
// are exact too, only slower (their rings reach across the grid).
#include <array>
#include <cstdint>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

class CentroidGrid {
 public:
  static constexpr Index kMaxDimensions = 3;

  CentroidGrid() = default;
  // `centroids`: one per row, k >= 1, 1 to kMaxDimensions columns, all finite.
  explicit CentroidGrid(const RowMatrix& centroids);

  Index dimensions() const { return d_; }
  // Buckets along each axis (1 beyond dimensions()).
  const std::array<Index, kMaxDimensions>& buckets() const { return buckets_; }

  // The nearest centroid to `point` (dimensions() coordinates), with its reference squared
  // distance into `distance`; -1 when a coordinate is NaN or infinite.
  Index find(const Real* point, double* distance) const;

 private:
  // The bucket of coordinate x along `axis`, clamped to the grid.
  Index bucket_along(Index axis, double x) const;
  // Lower edge of bucket b along `axis`.
  double edge(Index axis, Index b) const {
    const auto u = static_cast<std::size_t>(axis);
    return low_[u] + static_cast<double>(b) * width_[u];
  }

  Index d_ = 0;
  std::array<Index, kMaxDimensions> buckets_{1, 1, 1};
  std::array<double, kMaxDimensions> low_{}, width_{1, 1, 1}, inverse_{};
  double margin_ = 0.0;                 // how far rounding may put a centroid past its bucket's edge
  std::vector<std::int32_t> start_;     // by bucket (row-major over the axes), and one past the last
  std::vector<std::int32_t> index_;     // centroid indices in bucket order, increasing within a bucket
  std::vector<Real> coordinates_;       // their coordinates, dimensions() each, in the same order
};

}  // namespace qdmeta
