#pragma once
// The unstructured archive's neighbour index: points of any dimension d >= 1, each under an
// integer slot (below 2^31), in a uniform grid over their first two coordinates (128 x 128
// cells over [-4, 4]^2, where AURORA's z-scored codes live; the first coordinate alone when
// d = 1). Points beyond share the edge cells, which keeps queries exact, only slower.
//
// Storage is one array per coordinate, cell after cell in column-major order, each cell with
// room to spare (a free place holds NaN, which no distance comparison accepts): a column of
// cells is one contiguous range, whose distances vectorise. A cell that runs out of room makes
// the grid lay itself out again; reserve() lays it out for a known batch of points at once.
//
// Queries are exact: the `count` nearest under the order (squared distance, slot), the distance
// being float_squared_distance() below. Cells are visited in square rings around the query's
// cell until the distance from the query to the next ring exceeds the count-th best distance
// found, so the answer never depends on the grid's geometry or on the order inside a cell.
// ring_spans() exposes the rings themselves, for callers that answer several questions about
// one neighbourhood (the archive's insertion rule) in one pass.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "qdmeta/core/fused.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct Neighbour {
  Real squared_distance;
  Index slot;
  bool operator<(const Neighbour& o) const {
    return squared_distance < o.squared_distance || (squared_distance == o.squared_distance && slot < o.slot);
  }
};

// A neighbour as one integer in the same order: the squared distance's bits (non-negative
// floats order as their bits) above the slot, which must be below 2^32.
using NeighbourKey = std::uint64_t;
inline NeighbourKey neighbour_key(Real squared_distance, Index slot) {
  return (static_cast<NeighbourKey>(std::bit_cast<std::uint32_t>(squared_distance)) << 32) |
         static_cast<std::uint32_t>(slot);
}
inline Real key_squared_distance(NeighbourKey key) { return std::bit_cast<Real>(static_cast<std::uint32_t>(key >> 32)); }
inline Index key_slot(NeighbourKey key) { return static_cast<Index>(key & 0xffffffffu); }

// The `count` smallest keys offered so far, in increasing order (an insertion into a short
// sorted array: the count is a novelty's k, about 15).
class NearestKeys {
 public:
  // Empties it for the `count` smallest keys; keys farther than `ceiling` (a squared distance
  // known to bound the count-th) need not be offered.
  void reset(std::size_t count, Real ceiling = std::numeric_limits<Real>::infinity()) {
    keys_.resize(count);
    size_ = 0;
    ceiling_ = ceiling;
  }
  void offer(NeighbourKey key) {
    std::size_t i;
    if (size_ == keys_.size()) {
      if (size_ == 0 || key >= keys_[size_ - 1]) return;
      i = size_ - 1;
    } else {
      i = size_++;
    }
    for (; i > 0 && keys_[i - 1] > key; --i) keys_[i] = keys_[i - 1];
    keys_[i] = key;
  }
  std::size_t size() const { return size_; }
  bool full() const { return size_ == keys_.size(); }
  NeighbourKey operator[](std::size_t i) const { return keys_[i]; }
  NeighbourKey back() const { return keys_[size_ - 1]; }
  // The squared distance a point must not exceed to be kept: the count-th one's, or the
  // ceiling while there are fewer.
  Real bar() const { return size_ == keys_.size() && size_ > 0 ? key_squared_distance(keys_[size_ - 1]) : ceiling_; }
  // sqrt of the i-th squared distance, in double (the insertion rule's distances).
  double distance(std::size_t i) const { return std::sqrt(static_cast<double>(key_squared_distance(keys_[i]))); }

 private:
  std::vector<NeighbourKey> keys_;
  std::size_t size_ = 0;
  Real ceiling_ = std::numeric_limits<Real>::infinity();
};

// Squared Euclidean distance in float, coordinates in order, one fused multiply-add each:
// (a0 - b0)^2, then + (a1 - b1)^2, ... Symmetric in a and b (a - b is exactly -(b - a)).
inline Real float_squared_distance(const Real* a, const Real* b, Index d) {
  Real sum = 0.0f;
  for (Index j = 0; j < d; ++j) {
    const Real diff = a[j] - b[j];
    sum = fused(diff, diff, sum);
  }
  return sum;
}

class PointGrid {
 public:
  explicit PointGrid(Index dimensions);

  Index dimensions() const { return d_; }
  Index size() const { return size_; }
  // `slot` (>= 0) must not be present; erase() requires it present.
  void insert(Index slot, const Real* point);
  void erase(Index slot);
  void clear();
  // Empties the grid and lays it out so that the `count` points (row-major) can be inserted
  // without a new layout.
  void reserve(const Real* points, Index count);

  // The `count` points nearest to `point` other than slot `excluded` (-1: none), nearest first,
  // into `out` (emptied first; fewer when the grid holds fewer).
  void nearest(const Real* point, Index count, Index excluded, std::vector<Neighbour>& out) const;

  // A range of storage places (one or more cells of a column). Valid until the grid changes.
  struct Span {
    std::int32_t begin, end;
  };
  // Appends the cells of ring r (r = 0: the query's own cell; r > 0: the cells at Chebyshev
  // distance r from it) to `spans`, and returns how far the rings 0..r reach: every point of
  // the grid closer to `query` than the returned distance is in one of them (+infinity once
  // they cover the grid). Rings are meant to be visited in order 0, 1, 2, ...
  double ring_spans(const Real* query, int r, std::vector<Span>& spans) const;
  // Offers every point of `span` but slot `excluded` to `best`, keyed by its squared distance
  // to `point`.
  void offer(const Span& span, const Real* point, Index excluded, NearestKeys& best) const;

 private:
  int axis_cell(Real x) const;
  std::int32_t cell_of(const Real* point) const;
  std::int32_t cell_index(int column, int row) const { return column * rows_ + row; }
  // Calls visit(begin, end) with the storage range of every column segment of ring r around
  // (column, row) inside the grid.
  template <class Visit>
  void for_ring(int column, int row, int r, Visit&& visit) const;
  // A lower bound on the distance from `query` (in cell (column, row)) to any point of ring r
  // or beyond; +infinity when ring r lies wholly outside the grid.
  double ring_distance(const Real* query, int column, int row, int r) const;
  // Lays the cells out with room for `wanted[c]` points in cell c plus spare room, keeping the
  // points present.
  void lay_out(const std::vector<std::int32_t>& wanted);

  Index d_;
  int rows_;  // cells along the second axis: 128, or 1 for d = 1
  Index size_ = 0;
  std::vector<std::vector<Real>> coordinates_;  // d arrays over the storage places
  std::vector<std::int32_t> slots_;             // by place: the slot there (-1: free)
  std::vector<std::int32_t> start_;             // by cell, and one past: cell c owns [start_[c], start_[c + 1])
  std::vector<std::int32_t> count_;             // by cell: its points fill the first count_[c] places
  std::vector<std::int32_t> place_;             // by slot: its place (-1: absent)
};

// Whether each of `count` points (row-major, d coordinates each) lies farther than `radius`
// from every earlier point: apart[i] = 1 when sqrt(float_squared_distance(p_i, p_j)), in double,
// exceeds `radius` for every j < i (the comparison of the archive's insertion rule). Spread over
// oneTBB's threads; the result does not depend on how many.
std::vector<std::uint8_t> rows_apart_from_earlier(const Real* points, Index count, Index d, double radius);

// The same, keeping its buffers from one call to the next.
class RowsApart {
 public:
  const std::vector<std::uint8_t>& find(const Real* points, Index count, Index d, double radius);

 private:
  std::vector<std::uint8_t> apart_;
  std::vector<std::int32_t> cell_of_, start_, next_, rows_;
  std::vector<Real> sorted_;  // the points in cell order
};

}  // namespace qdmeta
