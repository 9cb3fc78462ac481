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

CvtArchive::CvtArchive(CvtArchiveParams params, RowMatrix centroids)
    : params_(params), search_((params.validate(), std::move(centroids))) {
  list_length_ = std::min(params_.neighbours, cells());
  occupied_.assign(static_cast<std::size_t>(cells()), 0);
  objectives_.assign(static_cast<std::size_t>(cells()), 0);
  solutions_.resize(cells(), params_.solution_size);
  measures_.resize(cells(), dimensions());
  lists_.resize(cells(), list_length_);
}

Index CvtArchive::from_parent(const Real* x, Index parent) const {
  const Index d = dimensions();
  const double delta = std::sqrt(squared_distance(x, measures_.row(parent).data(), d));
  const std::int32_t* list = lists_.cells.row(parent).data();
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
    const double delta = std::sqrt(squared_distance(measures, measures_.row(parent).data(), d));
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

AddStatus CvtArchive::add(const Real* solution, Real objective, const Real* measures) {
  NeighbourLists one;
  one.resize(1, list_length_);
  neighbours_of(measures, -1, one, 0);
  return add_to_cell(index_of(measures), solution, objective, measures, one, 0);
}

AddStatus CvtArchive::add_to_cell(Index cell, const Real* solution, Real objective, const Real* measures,
                                  const NeighbourLists& lists, Index row) {
  auto& occ = occupied_[static_cast<std::size_t>(cell)];
  AddStatus status;
  if (!occ) {
    status = AddStatus::kNew;
    occ = 1;
    filled_.push_back(cell);
  } else if (objective > objectives_[static_cast<std::size_t>(cell)]) {
    status = AddStatus::kImproved;
  } else {
    return AddStatus::kNotAdded;
  }
  objectives_[static_cast<std::size_t>(cell)] = objective;
  std::copy_n(solution, params_.solution_size, solutions_.row(cell).data());
  std::copy_n(measures, dimensions(), measures_.row(cell).data());
  if (list_length_ > 0) {
    lists_.cells.row(cell) = lists.cells.row(row);
    lists_.distances.row(cell) = lists.distances.row(row);
    lists_.outside[static_cast<std::size_t>(cell)] = lists.outside[static_cast<std::size_t>(row)];
    lists_.slack[static_cast<std::size_t>(cell)] = lists.slack[static_cast<std::size_t>(row)];
  }
  return status;
}

void CvtArchive::clear() {
  for (Index c : filled_) occupied_[static_cast<std::size_t>(c)] = 0;
  filled_.clear();
}

ArchiveStats CvtArchive::stats() const {
  ArchiveStats s;
  s.num_elites = size();
  s.coverage = static_cast<double>(s.num_elites) / static_cast<double>(cells());
  if (filled_.empty()) return s;
  double sum = 0.0;
  double best = -std::numeric_limits<double>::infinity();
  for (Index c : filled_) {
    const double f = objectives_[static_cast<std::size_t>(c)];
    sum += f;
    best = std::max(best, f);
  }
  s.obj_max = best;
  s.obj_mean = sum / static_cast<double>(s.num_elites);
  s.qd_score = sum - params_.qd_offset * static_cast<double>(s.num_elites);
  s.norm_qd_score = s.qd_score / static_cast<double>(cells());
  return s;
}


void CvtArchive::save(BinaryWriter& out) const {
  out.tag("cvt_archive");
  out.value<std::int64_t>(cells());
  out.value<std::int64_t>(dimensions());
  out.value<std::int64_t>(params_.solution_size);
  const auto n = static_cast<Index>(filled_.size());
  std::vector<std::int64_t> cells(filled_.begin(), filled_.end());
  std::vector<Real> objectives;
  RowMatrix solutions(n, params_.solution_size), measures(n, dimensions());
  for (Index i = 0; i < n; ++i) {
    const Index c = filled_[static_cast<std::size_t>(i)];
    objectives.push_back(objectives_[static_cast<std::size_t>(c)]);
    solutions.row(i) = solutions_.row(c);
    measures.row(i) = measures_.row(c);
  }
  out.values(cells);
  out.values(objectives);
  out.matrix(solutions);
  out.matrix(measures);
}

void CvtArchive::load(BinaryReader& in) {
  in.expect_tag("cvt_archive");
  const auto cells = in.value<std::int64_t>("CVT cells");
  const auto dims = in.value<std::int64_t>("CVT dimensions");
  const auto genes = in.value<std::int64_t>("CVT solution size");
  if (cells != this->cells() || dims != dimensions() || genes != params_.solution_size)
    in.fail(fmt::format("CVT archive of {} cells ({}-D, {} genes) does not fit this run's of {} cells ({}-D, {} genes)",
                        cells, dims, genes, this->cells(), dimensions(), params_.solution_size));
  const auto filled = in.values<std::int64_t>("CVT cells filled");
  const auto objectives = in.values<Real>("CVT objectives");
  RowMatrix solutions, measures;
  in.matrix(solutions, "CVT solutions");
  in.matrix(measures, "CVT measures");
  const auto n = static_cast<Index>(filled.size());
  if (static_cast<Index>(objectives.size()) != n || solutions.rows() != n || measures.rows() != n ||
      solutions.cols() != params_.solution_size || measures.cols() != dimensions())
    in.fail("CVT archive contents disagree in size");
  clear();
  for (Index i = 0; i < n; ++i) {
    add(solutions.row(i).data(), objectives[static_cast<std::size_t>(i)], measures.row(i).data());
    if (filled_.size() != static_cast<std::size_t>(i + 1) || filled_.back() != filled[static_cast<std::size_t>(i)])
      in.fail(fmt::format("CVT elite {} does not fall in its saved cell {}: other centroids?", i,
                          filled[static_cast<std::size_t>(i)]));
  }
}

}  // namespace qdmeta
