#include "qdmeta/archive/cvt_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "qdmeta/archive/fast_distance.hpp"
#include "qdmeta/core/huge_pages.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CvtArchiveParams::validate() const {
  require_at_least("archive solution size", solution_size, Index{1});
  require_range("cvt.neighbours", neighbours, Index{0}, Index{100'000});
}

namespace {
// Centroid rows prefetched at the start of a parent-list walk (walks read about 24).
constexpr Index kPrefetchRows = 24;
// How far ahead a walk prefetches the rows it reads next.
constexpr Index kWalkAhead = 8;

EliteStoreShape store_shape(const CvtArchiveParams& p, const RowMatrix& centroids) {
  p.validate();
  return {centroids.rows(), p.solution_size, centroids.cols(), 0, p.qd_offset};
}
}  // namespace

CvtArchive::CvtArchive(CvtArchiveParams params, RowMatrix centroids)
    : CvtCentroidSearch{NearestCentroid((params.validate(), std::move(centroids)))},
      EliteStore(store_shape(params, search_.centroids())),
      params_(params) {
  list_length_ = std::min(params_.neighbours, cells());
  lists_.resize(cells(), list_length_);
  // Walks read two random rows of the lists (20 MB at the paper's sizes) per offspring: with
  // 4 KiB pages most of those reads would also miss the TLB. Not touched yet by resize().
  advise_huge_pages(lists_.cells.data(), static_cast<std::size_t>(lists_.cells.size()) * sizeof(std::int32_t));
  advise_huge_pages(lists_.distances.data(), static_cast<std::size_t>(lists_.distances.size()) * sizeof(Real));
}

void CvtArchive::prefetch_list(Index parent) const {
  // Lines of the entries a typical walk reads (about 24) and the parent's descriptor.
  const Index entries = std::min<Index>(list_length_, kPrefetchRows);
  const char* cells = reinterpret_cast<const char*>(lists_.cells.row(parent).data());
  const char* distances = reinterpret_cast<const char*>(lists_.distances.row(parent).data());
  for (Index b = 0; b < entries * 4; b += 64) {
    __builtin_prefetch(cells + b);
    __builtin_prefetch(distances + b);
  }
  const Index d = dimensions();
  __builtin_prefetch(measures(parent));
  __builtin_prefetch(measures(parent) + d - 1);
  __builtin_prefetch(&lists_.slack[static_cast<std::size_t>(parent)]);
  __builtin_prefetch(&lists_.outside[static_cast<std::size_t>(parent)]);
}

void CvtArchive::prefetch_rows(Index parent) const {
  const Index d = dimensions();
  const std::int32_t* list = lists_.cells.row(parent).data();
  const Index entries = std::min<Index>(list_length_, kPrefetchRows);
  for (Index i = 0; i < entries; ++i) {
    const Real* row = search_.centroids().row(list[i]).data();
    __builtin_prefetch(row);
    __builtin_prefetch(row + d - 1);
  }
}

Index CvtArchive::from_parent(const Real* x, Index parent) const {
  const Index d = dimensions();
  const std::int32_t* list = lists_.cells.row(parent).data();
  // The walk runs on fast distances (fast_distance.hpp); each is within `rel` of the exact
  // real sum, and so is the reference, so widening by `rel` keeps every bound on the safe side.
  const double rel = distance_relative_error(d);
  const double wide = 1 + std::max(rel, 1e-12);
  const double delta = std::sqrt(fast_squared_distance(x, measures(parent), d)) * wide;
  const Real* listed = lists_.distances.row(parent).data();
  const double slack = lists_.slack[static_cast<std::size_t>(parent)];
  // Scratch in locals (a thread_local reached through the TLS block on every entry cost
  // measurably): on the stack for the usual sizes.
  constexpr Index kStack = 512;
  double fast_stack[kStack], point_stack[kStack];
  thread_local std::vector<double> fast_heap, point_heap;
  double* fast = fast_stack;
  double* point = point_stack;
  if (list_length_ > kStack) {
    fast_heap.resize(static_cast<std::size_t>(list_length_));
    fast = fast_heap.data();
  }
  if (d > kStack) {
    point_heap.resize(static_cast<std::size_t>(d));
    point = point_heap.data();
  }
  std::copy_n(x, d, point);
  double best_fast = std::numeric_limits<double>::infinity();
  double best_bound = best_fast;  // above the true distance to the nearest walked centroid
  Index walked = 0;
  for (; walked < list_length_; ++walked) {
    // Listed distances are lower bounds rounded to float (relative error under 1e-7); the
    // margins keep every bound below the truth despite that and the double rounding here.
    const double lower = static_cast<double>(listed[walked]) * (1 - 1e-6) - slack - delta - 1e-12;
    if (lower > best_bound) break;  // the list is sorted: no later entry can be as near
    // Past the rows prefetched before the walk, the loads are started a few entries ahead.
    if (walked + kWalkAhead < list_length_) {
      if ((walked & 15) == 0 && walked + 2 * kWalkAhead < list_length_) {
        __builtin_prefetch(list + walked + 2 * kWalkAhead);
        __builtin_prefetch(listed + walked + 2 * kWalkAhead);
      }
      const Real* ahead = search_.centroids().row(list[walked + kWalkAhead]).data();
      __builtin_prefetch(ahead);
      __builtin_prefetch(ahead + d - 1);
    }
    const double f = fast_squared_distance(point, search_.centroids().row(list[walked]).data(), d);
    fast[walked] = f;
    if (f < best_fast) {
      best_fast = f;
      best_bound = std::sqrt(f) * wide;
    }
  }
  // The reference distance decides among the walked entries that may tie with the best: any
  // entry further than this in fast distance is further in the reference one too.
  const double cut = best_fast * (1 + 4 * rel) + std::numeric_limits<double>::min();
  Index best = -1;
  double best_squared = std::numeric_limits<double>::infinity();
  for (Index i = 0; i < walked; ++i) {
    if (fast[i] > cut) continue;
    const Index c = list[i];
    const double squared = squared_distance(x, search_.centroids().row(c).data(), d);
    if (squared < best_squared || (squared == best_squared && c < best)) {
      best_squared = squared;
      best = c;
    }
  }
  const double best_distance = std::sqrt(best_squared) * wide;
  const double outside = lists_.outside[static_cast<std::size_t>(parent)] - delta - 1e-12;
  return best >= 0 && outside > best_distance ? best : -1;
}

Index CvtArchive::locate(const Real* measures, Index count, const Index* parents, Index* cells,
                         std::uint8_t* settled) const {
  const Index d = dimensions();
  std::vector<Index> searched;  // rows that need the full search
  // Walks are bound by memory latency: random parents' lists, then random centroid rows. A
  // software pipeline hides it: the list of row r + 2 and the centroid rows of row r + 1 are
  // fetched while row r walks.
  const bool walks = parents && list_length_ > 0;
  const auto parent_of = [&](Index r) { return walks && r < count && parents[r] >= 0 && occupied(parents[r]) ? parents[r] : -1; };
  for (Index r = 0; r < 2; ++r)
    if (parent_of(r) >= 0) prefetch_list(parent_of(r));
  if (parent_of(0) >= 0) prefetch_rows(parent_of(0));
  for (Index r = 0; r < count; ++r) {
    if (parent_of(r + 2) >= 0) prefetch_list(parent_of(r + 2));
    if (parent_of(r + 1) >= 0) prefetch_rows(parent_of(r + 1));
    const Index p = parent_of(r);
    const Index cell = p >= 0 ? from_parent(measures + r * d, p) : -1;
    if (settled) settled[r] = cell >= 0;
    if (cell >= 0) cells[r] = cell;
    else searched.push_back(r);
  }
  if (searched.empty()) return 0;
  RowMatrix block(static_cast<Index>(searched.size()), d);
  for (std::size_t i = 0; i < searched.size(); ++i)
    std::copy_n(measures + searched[i] * d, d, block.row(static_cast<Index>(i)).data());
  std::vector<Index> found(searched.size());
  search_.find(block.data(), block.rows(), found.data());
  for (std::size_t i = 0; i < searched.size(); ++i) cells[searched[i]] = found[i];
  return static_cast<Index>(searched.size());
}

bool CvtArchive::inherit_list(const Real* measures, Index parent, NeighbourLists& lists, Index row) const {
  if (list_length_ == 0) return true;
  if (parent < 0) return false;
  const Index d = dimensions();
  const auto u = static_cast<std::size_t>(row), p = static_cast<std::size_t>(parent);
  const double delta =
      std::sqrt(fast_squared_distance(measures, this->measures(parent), d)) * (1 + std::max(distance_relative_error(d), 1e-12));
  // Kept a hair wide (slack) and low (outside) against the rounding of delta.
  const double slack = (lists_.slack[p] + delta) * (1 + 1e-12) + 1e-12;
  const double outside = (lists_.outside[p] - delta) * (1 - 1e-12) - 1e-12;
  // The bound wears down along a line of descent; once its margin over the nearest centroid
  // falls under a fifth of that distance, most offspring would fail it and need the full
  // search, so the list is remade from all centroids instead.
  const double nearest = std::sqrt(fast_squared_distance(measures, search_.centroids().row(lists_.cells(parent, 0)).data(), d));
  if (outside - nearest < 0.2 * nearest) return false;
  lists.cells.row(row) = lists_.cells.row(parent);
  lists.distances.row(row) = lists_.distances.row(parent);
  lists.slack[u] = slack;
  lists.outside[u] = outside;
  return true;
}

void CvtArchive::remake_lists(const Real* measures, Index count, const Index* rows, NeighbourLists& lists) const {
  if (list_length_ == 0) return;
  // Made kValueRows at a time (the centroids streamed once per block), then copied to their rows.
  thread_local NeighbourLists block;
  block.resize(kValueRows, list_length_);
  const Index d = dimensions();
  for (Index first = 0; first < count; first += kValueRows) {
    const Index n = std::min(kValueRows, count - first);
    search_.neighbours(measures + first * d, n, list_length_, block.cells.data(), block.distances.data(), block.outside.data());
    for (Index i = 0; i < n; ++i) {
      const Index row = rows[first + i];
      const auto u = static_cast<std::size_t>(row);
      lists.cells.row(row) = block.cells.row(i);
      lists.distances.row(row) = block.distances.row(i);
      lists.outside[u] = block.outside[static_cast<std::size_t>(i)];
      lists.slack[u] = 0.0;
    }
  }
}

void CvtArchive::neighbours_of(const Real* measures, Index parent, NeighbourLists& lists, Index row) const {
  if (!inherit_list(measures, parent, lists, row)) remake_lists(measures, 1, &row, lists);
}

Index CvtArchive::add_batch(const EliteBatch& batch, std::span<AddStatus> status, const Index* parents) {
  const Index d = dimensions();
  check_batch(batch, status.size(), solution_size(), d, 0, "CVT archive");
  const Index rows = batch.rows();
  // locate() reads contiguous rows; invalid rows (whose measures a task may leave undefined)
  // are zeroed and get a cell that is never used.
  batch_measures_.resize(rows, d);
  for (Index r = 0; r < rows; ++r) {
    if (batch.is_valid(r)) std::copy_n(batch.measures.row(r), d, batch_measures_.row(r).data());
    else batch_measures_.row(r).setZero();
  }
  batch_cells_.resize(static_cast<std::size_t>(rows));
  batch_settled_.assign(static_cast<std::size_t>(rows), 0);
  locate(batch_measures_.data(), rows, parents, batch_cells_.data(), batch_settled_.data());
  batch_list_.resize(1, list_length_);
  Index added = 0;
  for (Index r = 0; r < rows; ++r) {
    const auto u = static_cast<std::size_t>(r);
    const Index cell = batch_cells_[u];
    const Real f = batch.objectives[u];
    AddStatus s = AddStatus::kNotAdded;
    if (batch.is_valid(r) && would_enter(cell, f)) {
      const Real* m = batch_measures_.row(r).data();
      neighbours_of(m, batch_settled_[u] ? parents[r] : -1, batch_list_, 0);
      s = add_to_cell(cell, batch.solutions.row(r), f, m, batch_list_, 0);
    }
    added += s != AddStatus::kNotAdded;
    if (!status.empty()) status[u] = s;
  }
  return added;
}

AddStatus CvtArchive::add(std::span<const Real> solution, Real objective, std::span<const Real> measures) {
  const EliteBatch one{{solution.data(), 1, static_cast<Index>(solution.size())},
                       {&objective, 1},
                       {measures.data(), 1, static_cast<Index>(measures.size())},
                       {},
                       {}};
  AddStatus status;
  add_batch(one, {&status, 1});
  return status;
}

AddStatus CvtArchive::add_to_cell(Index cell, const Real* solution, Real objective, const Real* measures,
                                  const NeighbourLists& lists, Index row) {
  const AddStatus status = place(cell, solution, objective, measures, nullptr);
  if (status != AddStatus::kNotAdded && list_length_ > 0) {
    lists_.cells.row(cell) = lists.cells.row(row);
    lists_.distances.row(cell) = lists.distances.row(row);
    lists_.outside[static_cast<std::size_t>(cell)] = lists.outside[static_cast<std::size_t>(row)];
    lists_.slack[static_cast<std::size_t>(cell)] = lists.slack[static_cast<std::size_t>(row)];
  }
  return status;
}

void CvtArchive::save(BinaryWriter& out) const {
  out.tag("cvt_archive");
  out.value<std::int64_t>(cells());
  out.value<std::int64_t>(dimensions());
  out.value<std::int64_t>(params_.solution_size);
  save_elites(out, false);
}

void CvtArchive::load(BinaryReader& in) {
  in.expect_tag("cvt_archive");
  const auto cells = in.value<std::int64_t>("CVT cells");
  const auto dims = in.value<std::int64_t>("CVT dimensions");
  const auto genes = in.value<std::int64_t>("CVT solution size");
  if (cells != this->cells() || dims != dimensions() || genes != params_.solution_size)
    in.fail(fmt::format("CVT archive of {} cells ({}-D, {} genes) does not fit this run's of {} cells ({}-D, {} genes)",
                        cells, dims, genes, this->cells(), dimensions(), params_.solution_size));
  const SavedElites saved = read_elites(in, false, "CVT");
  remove_all();  // a load is not a clear (EliteStore::clears)
  // Re-added one at a time (cells found again, lists made afresh), checking each lands where it was.
  for (Index i = 0; i < saved.size(); ++i) {
    add({saved.solutions.row(i).data(), static_cast<std::size_t>(saved.solutions.cols())},
        saved.objectives[static_cast<std::size_t>(i)],
        {saved.measures.row(i).data(), static_cast<std::size_t>(saved.measures.cols())});
    if (filled_cells().size() != static_cast<std::size_t>(i + 1) ||
        filled_cells().back() != saved.cells[static_cast<std::size_t>(i)])
      in.fail(fmt::format("CVT elite {} does not fall in its saved cell {}: other centroids?", i,
                          saved.cells[static_cast<std::size_t>(i)]));
  }
}

}  // namespace qdmeta
