#pragma once
// Exact nearest-centroid search for CVT archives and k-means. Distances are first computed for
// blocks of points against all centroids as ||c||^2 - 2 x.c in float (centroid_values.hpp,
// at the multiply-add peak of the machine); every centroid whose float value lies within the
// product's rounding bound of the best is then re-checked with the exact reference distance
// (squared_distance below, in double), so the answer is the centroid the plain loop over all
// centroids would pick, ties broken by the lowest index. In 3 dimensions or fewer find() asks a
// bucket grid over the centroids instead (centroid_grid.hpp): the same answers, from a few dozen
// centroids rather than all.
#include <cstdint>
#include <optional>
#include <vector>

#include "qdmeta/archive/centroid_grid.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

// The reference: sum over i of (a_i - b_i)^2 in double, in index order, each product rounded
// before it is added (never fused: the same bits whatever the caller's compiler flags).
double squared_distance(const Real* a, const Real* b, Index dimensions);

// The reference search: the plain loop (for tests and as the definition of "exact").
Index nearest_centroid_naive(const RowMatrix& centroids, const Real* point);

class NearestCentroid {
 public:
  NearestCentroid() = default;
  // `centroids`: one per row (k x d), k >= 1, all finite.
  explicit NearestCentroid(RowMatrix centroids);

  Index count() const { return centroids_.rows(); }
  Index dimensions() const { return centroids_.cols(); }
  const RowMatrix& centroids() const { return centroids_; }

  // The nearest centroid of each of `count` points (row-major, dimensions() columns) into
  // `cells`; with `distances`, also the exact squared distance to it. Single-threaded: callers
  // split big batches into row ranges (each row's answer does not depend on the split).
  // The grid in 3 dimensions or fewer, else the blocked product.
  void find(const Real* points, Index count, Index* cells, double* distances = nullptr) const;
  Index find(const Real* point) const;
  // find() by the blocked product in any dimension (tests and benchmarks compare the two).
  void find_by_product(const Real* points, Index count, Index* cells, double* distances = nullptr) const;
  bool has_grid() const { return grid_.has_value(); }

  // A neighbour list for `point`: the `count` centroids with the smallest float distance values
  // (count <= count()), sorted by those values (ties to the lowest index), into `cells`, with a
  // lower bound on each one's distance into `distances` (non-decreasing, within the values'
  // rounding bound of the exact distance), and a lower bound on the distance from the point to
  // every centroid not in the list (infinity when the list holds them all).
  void neighbours(const Real* point, Index count, std::int32_t* cells, float* distances, double* outside) const {
    neighbours(point, 1, count, cells, distances, outside);
  }
  // The lists of `rows` points (row-major) at once, row r's at cells + r * count, distances +
  // r * count and outside[r]: the same lists as one point at a time, with the centroids
  // streamed once per kValueRows points (centroid_values.hpp).
  void neighbours(const Real* points, Index rows, Index count, std::int32_t* cells, float* distances,
                  double* outside) const;

 private:
  // One point's list from its values against every centroid.
  void select_list(const Real* point, const Real* values, Index count, std::int32_t* cells, float* distances,
                   double* outside) const;

  RowMatrix centroids_;
  std::optional<CentroidGrid> grid_;  // in CentroidGrid::kMaxDimensions or fewer
  std::vector<Real> blocked_;        // -2 C^T in blocks of 16 centroids (centroid_values.hpp)
  std::vector<Real> padded_norms_;   // ||c||^2, padded to whole blocks
  Vector norms_;                                                     // ||c||^2 in float
  double max_norm_ = 0.0;                                            // max ||c||
};

}  // namespace qdmeta
