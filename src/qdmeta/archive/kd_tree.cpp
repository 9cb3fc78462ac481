#include "qdmeta/archive/kd_tree.hpp"

#include <nanoflann.hpp>

#include <vector>

namespace qdmeta {
namespace {

// nanoflann's view of the points (its dataset adaptor protocol).
struct PointRows {
  std::vector<double> values;
  std::size_t dim;
  std::size_t kdtree_get_point_count() const { return values.size() / dim; }
  double kdtree_get_pt(std::size_t row, std::size_t d) const { return values[row * dim + d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;  // let the tree compute it
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointRows>, PointRows, -1,
                                                 std::size_t>;

}  // namespace

struct KdTree::Impl {
  PointRows rows;
  Tree tree;
  Impl(std::span<const double> points, std::size_t dim)
      : rows{{points.begin(), points.end()}, dim},
        tree(static_cast<int>(dim), rows, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

KdTree::KdTree(std::span<const double> points, std::size_t dim) : impl_(std::make_unique<Impl>(points, dim)) {}
KdTree::~KdTree() = default;

std::size_t KdTree::size() const { return impl_->rows.kdtree_get_point_count(); }

std::size_t KdTree::nearest(const double* query, std::size_t k, std::size_t* rows, double* squared_distances) const {
  if (size() == 0 || k == 0) return 0;
  return impl_->tree.knnSearch(query, k, rows, squared_distances);
}

}  // namespace qdmeta
