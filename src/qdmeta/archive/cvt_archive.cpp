#include "qdmeta/archive/cvt_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CvtArchiveParams::validate() const { require_at_least("archive solution size", solution_size, Index{1}); }

CvtArchive::CvtArchive(CvtArchiveParams params, RowMatrix centroids)
    : params_(params), search_((params.validate(), std::move(centroids))) {
  occupied_.assign(static_cast<std::size_t>(cells()), 0);
  objectives_.assign(static_cast<std::size_t>(cells()), 0);
  bounds_.assign(static_cast<std::size_t>(cells()), 0.0);
  solutions_.resize(cells(), params_.solution_size);
  measures_.resize(cells(), dimensions());
}

void CvtArchive::locate(const Real* measures, Index count, const Index* parents, Index* cells, double* bounds) const {
  const Index d = dimensions();
  std::vector<Index> searched;  // rows that need the full search
  for (Index r = 0; r < count; ++r) {
    const Real* x = measures + r * d;
    const Index p = parents ? parents[r] : -1;
    if (p >= 0 && occupied(p)) {
      const double delta = std::sqrt(squared_distance(x, measures_.row(p).data(), d));
      const double own = std::sqrt(squared_distance(x, search_.centroids().row(p).data(), d));
      const double others = bounds_[static_cast<std::size_t>(p)] - delta;
      // The margin covers the rounding of the double distances (relative 1e-16).
      if (own < others - 1e-9 * (others + own + delta)) {
        cells[r] = p;
        bounds[r] = others * (1 - 1e-12) - 1e-12 * delta;  // kept a hair low against rounding
        continue;
      }
    }
    searched.push_back(r);
  }
  if (searched.empty()) return;
  RowMatrix block(static_cast<Index>(searched.size()), d);
  for (std::size_t i = 0; i < searched.size(); ++i)
    std::copy_n(measures + searched[i] * d, d, block.row(static_cast<Index>(i)).data());
  std::vector<Index> found(searched.size());
  std::vector<double> found_bounds(searched.size());
  search_.find(block.data(), block.rows(), found.data(), nullptr, found_bounds.data());
  for (std::size_t i = 0; i < searched.size(); ++i) {
    cells[searched[i]] = found[i];
    bounds[searched[i]] = found_bounds[i];
  }
}

AddStatus CvtArchive::add(const Real* solution, Real objective, const Real* measures) {
  Index cell = 0;
  double bound = 0.0;
  locate(measures, 1, nullptr, &cell, &bound);
  return add_to_cell(cell, bound, solution, objective, measures);
}

AddStatus CvtArchive::add_to_cell(Index cell, double bound, const Real* solution, Real objective, const Real* measures) {
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
  bounds_[static_cast<std::size_t>(cell)] = bound;
  std::copy_n(solution, params_.solution_size, solutions_.row(cell).data());
  std::copy_n(measures, dimensions(), measures_.row(cell).data());
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

}  // namespace qdmeta
