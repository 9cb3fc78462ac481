#include "qdmeta/archive/cvt_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void CvtArchiveParams::validate() const { require_at_least("archive solution size", solution_size, Index{1}); }

CvtArchive::CvtArchive(CvtArchiveParams params, RowMatrix centroids)
    : params_(params), search_((params.validate(), std::move(centroids))) {
  occupied_.assign(static_cast<std::size_t>(cells()), 0);
  objectives_.assign(static_cast<std::size_t>(cells()), 0);
  solutions_.resize(cells(), params_.solution_size);
  measures_.resize(cells(), dimensions());
}

AddStatus CvtArchive::add_to_cell(Index cell, const Real* solution, Real objective, const Real* measures) {
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
