#include "qdmeta/archive/point_grid.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define QDMETA_POINT_GRID_AVX2 1
#endif

namespace qdmeta {
namespace {

constexpr int kGridCells = 128;       // per grid axis
constexpr double kGridHalfWidth = 4;  // the grid spans [-4, 4] on each of its axes
constexpr double kCellSide = 2 * kGridHalfWidth / kGridCells;
// A cell index computed for a point within about 1e-14 of a cell edge may be the neighbour's;
// ring distances are shortened by this much so that such a point is never skipped.
constexpr double kEdgeMargin = 1e-3 * kCellSide;
constexpr std::int32_t kSpareRoom = 2;  // free places per cell after a layout
constexpr Real kFree = std::numeric_limits<Real>::quiet_NaN();

double cell_edge(int c) { return -kGridHalfWidth + c * kCellSide; }  // lower edge of cell c

// Squared distances of places [begin, end) to `query`, each offered to `best` unless farther
// than its bar (NaN, a free place, never passes) or the excluded slot. The distances are
// float_squared_distance()'s, eight places at a time where the CPU has AVX2 and FMA (the
// storage has room to read past `end`).
#if defined(QDMETA_POINT_GRID_AVX2)
void offer_places(const std::vector<std::vector<Real>>& coordinates, const std::int32_t* slots, std::int32_t begin,
                  std::int32_t end, const Real* query, Index excluded, NearestKeys& best) {
  const std::size_t d = coordinates.size();
  alignas(32) Real squared[8];
  for (std::int32_t first = begin; first < end; first += 8) {
    __m256 diff = _mm256_sub_ps(_mm256_loadu_ps(coordinates[0].data() + first), _mm256_set1_ps(query[0]));
    __m256 sum = _mm256_mul_ps(diff, diff);  // fma(diff, diff, 0)
    for (std::size_t j = 1; j < d; ++j) {
      diff = _mm256_sub_ps(_mm256_loadu_ps(coordinates[j].data() + first), _mm256_set1_ps(query[j]));
      sum = _mm256_fmadd_ps(diff, diff, sum);
    }
    unsigned passing =
        static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(sum, _mm256_set1_ps(best.bar()), _CMP_LE_OQ)));
    if (end - first < 8) passing &= (1u << (end - first)) - 1;
    if (passing == 0) continue;
    _mm256_store_ps(squared, sum);
    for (; passing != 0; passing &= passing - 1) {
      const int e = __builtin_ctz(passing);
      const std::int32_t slot = slots[first + e];
      if (slot != excluded && squared[e] <= best.bar()) best.offer(neighbour_key(squared[e], slot));
    }
  }
}
#else
void offer_places(const std::vector<std::vector<Real>>& coordinates, const std::int32_t* slots, std::int32_t begin,
                  std::int32_t end, const Real* query, Index excluded, NearestKeys& best) {
  const std::size_t d = coordinates.size();
  for (std::int32_t p = begin; p < end; ++p) {
    Real sum = 0.0f;
    for (std::size_t j = 0; j < d; ++j) {
      const Real diff = coordinates[j][static_cast<std::size_t>(p)] - query[j];
      sum = fused(diff, diff, sum);
    }
    if (sum <= best.bar() && slots[p] != excluded) best.offer(neighbour_key(sum, slots[p]));
  }
}
#endif

}  // namespace

PointGrid::PointGrid(Index dimensions)
    : d_(dimensions), rows_(dimensions > 1 ? kGridCells : 1), coordinates_(static_cast<std::size_t>(dimensions)) {
  lay_out(std::vector<std::int32_t>(static_cast<std::size_t>(kGridCells * rows_), 0));
}

int PointGrid::axis_cell(Real x) const {
  const double c = std::floor((static_cast<double>(x) + kGridHalfWidth) / kCellSide);
  return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(kGridCells - 1)));
}

std::int32_t PointGrid::cell_of(const Real* point) const {
  return cell_index(axis_cell(point[0]), rows_ > 1 ? axis_cell(point[1]) : 0);
}

void PointGrid::lay_out(const std::vector<std::int32_t>& wanted) {
  const std::size_t cells = wanted.size();
  std::vector<std::int32_t> start(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) start[c + 1] = start[c] + std::max(wanted[c], count_.empty() ? 0 : count_[c]) + kSpareRoom;
  const auto places = static_cast<std::size_t>(start[cells]);
  // Seven free places past the last cell, where a block of eight starting at its end reads.
  std::vector<std::vector<Real>> coordinates(coordinates_.size(), std::vector<Real>(places + 7, kFree));
  std::vector<std::int32_t> slots(places, -1);
  if (!count_.empty()) {
    for (std::size_t c = 0; c < cells; ++c) {
      for (std::int32_t e = 0; e < count_[c]; ++e) {
        const auto from = static_cast<std::size_t>(start_[c] + e), to = static_cast<std::size_t>(start[c] + e);
        for (std::size_t j = 0; j < coordinates.size(); ++j) coordinates[j][to] = coordinates_[j][from];
        slots[to] = slots_[from];
        place_[static_cast<std::size_t>(slots_[from])] = static_cast<std::int32_t>(to);
      }
    }
  } else {
    count_.assign(cells, 0);
  }
  coordinates_ = std::move(coordinates);
  slots_ = std::move(slots);
  start_ = std::move(start);
}

void PointGrid::insert(Index slot, const Real* point) {
  const std::int32_t c = cell_of(point);
  const auto cell = static_cast<std::size_t>(c);
  if (start_[cell] + count_[cell] == start_[cell + 1]) {  // no room left: lay out again
    std::vector<std::int32_t> wanted(count_);
    ++wanted[cell];
    lay_out(wanted);
  }
  const auto at = static_cast<std::size_t>(start_[cell] + count_[cell]++);
  for (std::size_t j = 0; j < coordinates_.size(); ++j) coordinates_[j][at] = point[j];
  slots_[at] = static_cast<std::int32_t>(slot);
  const auto s = static_cast<std::size_t>(slot);
  if (s >= place_.size()) place_.resize(s + 1, -1);
  place_[s] = static_cast<std::int32_t>(at);
  ++size_;
}

void PointGrid::erase(Index slot) {
  const auto at = static_cast<std::size_t>(place_[static_cast<std::size_t>(slot)]);
  Real point[2] = {coordinates_[0][at], d_ > 1 ? coordinates_[1][at] : 0.0f};
  const auto cell = static_cast<std::size_t>(cell_of(point));
  const auto last = static_cast<std::size_t>(start_[cell] + --count_[cell]);
  if (at != last) {  // the cell's last point takes the freed place: order inside a cell does not matter
    for (auto& c : coordinates_) c[at] = c[last];
    slots_[at] = slots_[last];
    place_[static_cast<std::size_t>(slots_[at])] = static_cast<std::int32_t>(at);
  }
  for (auto& c : coordinates_) c[last] = kFree;
  slots_[last] = -1;
  place_[static_cast<std::size_t>(slot)] = -1;
  --size_;
}

void PointGrid::clear() {
  if (size_ == 0) return;
  for (std::size_t c = 0; c + 1 < start_.size(); ++c) {
    for (auto p = static_cast<std::size_t>(start_[c]); p < static_cast<std::size_t>(start_[c] + count_[c]); ++p) {
      for (auto& x : coordinates_) x[p] = kFree;
      slots_[p] = -1;
    }
    count_[c] = 0;
  }
  place_.clear();
  size_ = 0;
}

void PointGrid::reserve(const Real* points, Index count) {
  // A new layout in place (the buffers keep their capacity): each cell's room from the points
  // that will come to it.
  const std::size_t cells = count_.size();
  start_.assign(cells + 1, 0);
  for (Index i = 0; i < count; ++i) ++start_[static_cast<std::size_t>(cell_of(points + i * d_)) + 1];
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c] + kSpareRoom;
  const auto places = static_cast<std::size_t>(start_[cells]);
  for (auto& x : coordinates_) x.assign(places + 7, kFree);  // as lay_out(): room to read past the end
  slots_.assign(places, -1);
  count_.assign(cells, 0);
  place_.clear();
  size_ = 0;
}

template <class Visit>
void PointGrid::for_ring(int column, int row, int r, Visit&& visit) const {
  const auto cells = [&](int x, int y_from, int y_to) {  // cells y_from..y_to of column x, one range
    visit(start_[static_cast<std::size_t>(cell_index(x, y_from))],
          start_[static_cast<std::size_t>(cell_index(x, y_to)) + 1]);
  };
  if (r == 0) {
    cells(column, row, row);
    return;
  }
  const int x0 = column - r, x1 = column + r, y0 = row - r, y1 = row + r;
  for (int x = std::max(x0, 0); x <= std::min(x1, kGridCells - 1); ++x) {
    if (x == x0 || x == x1) {  // a full column of the ring
      cells(x, std::max(y0, 0), std::min(y1, rows_ - 1));
    } else {  // only its top and bottom cells
      if (y0 >= 0) cells(x, y0, y0);
      if (y1 < rows_) cells(x, y1, y1);
    }
  }
}

double PointGrid::ring_distance(const Real* query, int column, int row, int r) const {
  // Every point of ring r lies past one of the ring's sides that has cells (a point clamped
  // into an edge cell lies farther still), and so does every point of the rings beyond.
  const double qx = query[0];
  double bound = std::numeric_limits<double>::infinity();
  if (column - r >= 0) bound = std::min(bound, qx - cell_edge(column - r + 1));
  if (column + r < kGridCells) bound = std::min(bound, cell_edge(column + r) - qx);
  if (rows_ > 1) {
    const double qy = query[1];
    if (row - r >= 0) bound = std::min(bound, qy - cell_edge(row - r + 1));
    if (row + r < rows_) bound = std::min(bound, cell_edge(row + r) - qy);
  }
  return bound == std::numeric_limits<double>::infinity() ? bound : bound - kEdgeMargin;
}

void PointGrid::offer(const Span& span, const Real* point, Index excluded, NearestKeys& best) const {
  offer_places(coordinates_, slots_.data(), span.begin, span.end, point, excluded, best);
}

void PointGrid::nearest(const Real* point, Index count, Index excluded, std::vector<Neighbour>& out) const {
  out.clear();
  if (count <= 0 || size_ == 0) return;
  NearestKeys best;
  best.reset(static_cast<std::size_t>(count));
  const int cx = axis_cell(point[0]), cy = rows_ > 1 ? axis_cell(point[1]) : 0;
  for (int r = 0;; ++r) {
    if (r > 0) {
      const double bound = ring_distance(point, cx, cy, r);
      if (bound == std::numeric_limits<double>::infinity()) break;  // every cell visited
      if (best.full() && bound > 0 && bound * bound > static_cast<double>(best.bar())) break;
    }
    for_ring(cx, cy, r, [&](std::int32_t begin, std::int32_t end) { offer({begin, end}, point, excluded, best); });
  }
  for (std::size_t i = 0; i < best.size(); ++i) out.push_back({key_squared_distance(best[i]), key_slot(best[i])});
}

double PointGrid::ring_spans(const Real* query, int r, std::vector<Span>& spans) const {
  const int cx = axis_cell(query[0]), cy = rows_ > 1 ? axis_cell(query[1]) : 0;
  for_ring(cx, cy, r, [&](std::int32_t begin, std::int32_t end) { spans.push_back({begin, end}); });
  return ring_distance(query, cx, cy, r + 1);
}

const std::vector<std::uint8_t>& RowsApart::find(const Real* points, Index count, Index d, double radius) {
  apart_.assign(static_cast<std::size_t>(std::max<Index>(count, 0)), 1);
  if (count < 2 || radius < 0) return apart_;  // every distance exceeds a negative radius
  if (!std::isfinite(radius)) {                // none exceeds +infinity or NaN
    std::fill(apart_.begin() + 1, apart_.end(), std::uint8_t{0});
    return apart_;
  }
  // The largest float squared distance whose square root, in double, is not beyond the
  // radius: "near" is then one float comparison, the rule's own answer.
  auto within = [&](Real t) { return std::sqrt(static_cast<double>(t)) <= radius; };
  Real bar = static_cast<Real>(radius * radius);
  while (!within(bar)) bar = std::nextafter(bar, 0.0f);
  while (within(std::nextafter(bar, std::numeric_limits<Real>::infinity())))
    bar = std::nextafter(bar, std::numeric_limits<Real>::infinity());
  // A static grid over the points' bounding box (first two coordinates) with cells wider than
  // the radius, so that any point within the radius of another lies in one of the 3 x 3 cells
  // around it; at most about 4 cells per point.
  const Index axes = std::min<Index>(d, 2);
  double lo[2] = {0.0, 0.0}, side[2] = {1.0, 1.0};
  int cells[2] = {1, 1};
  const double most = std::max(1.0, std::floor(std::sqrt(4.0 * static_cast<double>(count))));
  for (Index a = 0; a < axes; ++a) {
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (Index i = 0; i < count; ++i) {
      low = std::min(low, static_cast<double>(points[i * d + a]));
      high = std::max(high, static_cast<double>(points[i * d + a]));
    }
    const double extent = high - low;
    const double n = std::clamp(std::floor(extent / (1.001 * radius)), 1.0, most);
    lo[a] = low;
    cells[a] = static_cast<int>(n);
    side[a] = extent > 0 ? extent / n : 1.0;
  }
  const auto axis_cell = [&](Index i, Index a) {
    const double c = std::floor((static_cast<double>(points[i * d + a]) - lo[a]) / side[a]);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(cells[a] - 1)));
  };
  // Rows sorted by cell, column-major (counting sort), with their coordinates beside: the
  // three cells of a column around a row are one range.
  const auto total = static_cast<std::size_t>(cells[0]) * static_cast<std::size_t>(cells[1]);
  cell_of_.resize(static_cast<std::size_t>(count));
  start_.assign(total + 1, 0);
  for (Index i = 0; i < count; ++i) {
    const int c = axis_cell(i, 0) * cells[1] + (axes > 1 ? axis_cell(i, 1) : 0);
    cell_of_[static_cast<std::size_t>(i)] = c;
    ++start_[static_cast<std::size_t>(c) + 1];
  }
  for (std::size_t c = 0; c < total; ++c) start_[c + 1] += start_[c];
  next_.assign(start_.begin(), start_.end() - 1);
  rows_.resize(static_cast<std::size_t>(count));
  sorted_.resize(static_cast<std::size_t>(count * d));
  for (Index i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>(next_[static_cast<std::size_t>(cell_of_[static_cast<std::size_t>(i)])]++);
    rows_[k] = static_cast<std::int32_t>(i);
    std::copy_n(points + i * d, d, sorted_.data() + k * static_cast<std::size_t>(d));
  }
  tbb::parallel_for(tbb::blocked_range<Index>(1, count, 256), [&](const tbb::blocked_range<Index>& range) {
    for (Index i = range.begin(); i < range.end(); ++i) {
      const Real* p = points + i * d;
      const int c = cell_of_[static_cast<std::size_t>(i)];
      const int cx = c / cells[1], cy = c % cells[1];
      const int y0 = std::max(cy - 1, 0), y1 = std::min(cy + 1, cells[1] - 1);
      bool near = false;
      for (int x = std::max(cx - 1, 0); x <= std::min(cx + 1, cells[0] - 1) && !near; ++x) {
        const auto first = static_cast<std::size_t>(start_[static_cast<std::size_t>(x * cells[1] + y0)]);
        const auto last = static_cast<std::size_t>(start_[static_cast<std::size_t>(x * cells[1] + y1) + 1]);
        for (std::size_t k = first; k < last; ++k) {
          if (rows_[k] < i && float_squared_distance(sorted_.data() + k * static_cast<std::size_t>(d), p, d) <= bar) {
            near = true;
            break;
          }
        }
      }
      apart_[static_cast<std::size_t>(i)] = near ? 0 : 1;
    }
  });
  return apart_;
}

std::vector<std::uint8_t> rows_apart_from_earlier(const Real* points, Index count, Index d, double radius) {
  RowsApart finder;
  return finder.find(points, count, d, radius);
}

}  // namespace qdmeta
