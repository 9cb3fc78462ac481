#include "qdmeta/archive/cvt_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CvtArchiveParams::validate() const {
  require_at_least("archive solution size", solution_size, Index{1});
  require_range("cvt.neighbours", neighbours, Index{0}, Index{100'000});
}

namespace {
// Centroid rows prefetched at the start of a parent-list walk (walks read about 24).
constexpr Index kPrefetchRows = 24;

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
}

Index CvtArchive::from_parent(const Real* x, Index parent) const {
  const Index d = dimensions();
  const std::int32_t* list = lists_.cells.row(parent).data();
  // The walk is bound by memory latency (random centroid rows, about 24 per walk): start the
  // loads of the first rows before the arithmetic so that they overlap.
  const Index ahead = std::min<Index>(list_length_, kPrefetchRows);
  for (Index i = 0; i < ahead; ++i) {
    const Real* row = search_.centroids().row(list[i]).data();
    __builtin_prefetch(row);
    __builtin_prefetch(row + d - 1);
  }
  const double delta = std::sqrt(squared_distance(x, measures(parent), d));
  const Real* listed = lists_.distances.row(parent).data();
  const double slack = lists_.slack[static_cast<std::size_t>(parent)];
  Index best = -1;
  double best_squared = std::numeric_limits<double>::infinity();
  double best_distance = best_squared;
  for (Index i = 0; i < list_length_; ++i) {
    // Listed distances are exact distances rounded to float (relative error under 1e-7); the
    // margins keep every bound below the truth despite that and the double rounding here.
    const double lower = static_cast<double>(listed[i]) * (1 - 1e-6) - slack - delta - 1e-12;
    if (lower > best_distance) break;  // the list is sorted: no later entry can be nearer
    const Index c = list[i];
    const double squared = squared_distance(x, search_.centroids().row(c).data(), d);
    if (squared < best_squared || (squared == best_squared && c < best)) {
      best_squared = squared;
      best = c;
      best_distance = std::sqrt(squared) * (1 + 1e-12);
    }
  }
  const double outside = lists_.outside[static_cast<std::size_t>(parent)] - delta - 1e-12;
  return best >= 0 && outside > best_distance ? best : -1;
}

Index CvtArchive::locate(const Real* measures, Index count, const Index* parents, Index* cells,
                         std::uint8_t* settled) const {
  const Index d = dimensions();
  std::vector<Index> searched;  // rows that need the full search
  for (Index r = 0; r < count; ++r) {
    const Index p = parents && list_length_ > 0 ? parents[r] : -1;
    const Index cell = p >= 0 && occupied(p) ? from_parent(measures + r * d, p) : -1;
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

void CvtArchive::neighbours_of(const Real* measures, Index parent, NeighbourLists& lists, Index row) const {
  if (list_length_ == 0) return;
  if (parent >= 0) {
    const Index d = dimensions();
    const auto u = static_cast<std::size_t>(row);
    const double delta = std::sqrt(squared_distance(measures, this->measures(parent), d));
    lists.cells.row(row) = lists_.cells.row(parent);
    lists.distances.row(row) = lists_.distances.row(parent);
    // Kept a hair wide (slack) and low (outside) against the rounding of delta.
    lists.slack[u] = (lists_.slack[static_cast<std::size_t>(parent)] + delta) * (1 + 1e-12) + 1e-12;
    lists.outside[u] = (lists_.outside[static_cast<std::size_t>(parent)] - delta) * (1 - 1e-12) - 1e-12;
    // The bound wears down along a line of descent; once its margin over the nearest centroid
    // falls under a fifth of that distance, most offspring would fail it and need the full
    // search, so the list is remade from all centroids instead.
    const double nearest = std::sqrt(squared_distance(measures, search_.centroids().row(lists_.cells(parent, 0)).data(), d));
    if (lists.outside[u] - nearest >= 0.2 * nearest) return;
  }
  search_.neighbours(measures, list_length_, lists.cells.row(row).data(), lists.distances.row(row).data(),
                     &lists.outside[static_cast<std::size_t>(row)]);
  lists.slack[static_cast<std::size_t>(row)] = 0.0;
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
  clear();
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
