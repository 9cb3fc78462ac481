#pragma once
// Exact k-nearest-neighbour queries over a fixed set of points of any dimension, in double: a
// k-d tree (Debian's nanoflann, kept out of this header) over a copy of the points, built once;
// the proximity archive builds a new one after each add that changes its elites, as pyribs
// rebuilds its scipy KDTree.
#include <cstddef>
#include <memory>
#include <span>

namespace qdmeta {

class KdTree {
 public:
  // `points` row-major, points.size() / dim rows; dim >= 1.
  KdTree(std::span<const double> points, std::size_t dim);
  ~KdTree();
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;

  std::size_t size() const;
  // The min(k, size()) nearest points to `query` (dim values), nearest first: their row indices
  // and squared Euclidean distances. Returns how many were written.
  std::size_t nearest(const double* query, std::size_t k, std::size_t* rows, double* squared_distances) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace qdmeta
