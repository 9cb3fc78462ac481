#include "qdmeta/archive/grid_archive.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

void GridArchiveParams::validate() const {
  if (bins.empty()) throw InputError("archive.bins is empty: give the number of bins of each target feature");
  double cells = 1;
  for (int b : bins) {
    if (b < 1) throw InputError(fmt::format("archive.bins = [{}] is out of range: each must be at least 1",
                                            fmt::join(bins, ", ")));
    cells *= b;
  }
  if (cells > 1e8)
    throw InputError(fmt::format("archive.bins = [{}] gives {} cells: at most 100,000,000 are allowed",
                                 fmt::join(bins, ", "), cells));
  if (!(lower < upper) || !std::isfinite(lower) || !std::isfinite(upper))
    throw InputError(fmt::format("archive range [{}, {}] is invalid: lower must be below upper", lower, upper));
  require_at_least("archive solution size", solution_size, Index{1});
  require_at_least("archive base-feature size", base_feature_size, Index{0});
  require_range("archive.epsilon", epsilon, 0.0, 0.5);
}

GridArchive::GridArchive(GridArchiveParams params) : params_(std::move(params)) {
  params_.validate();
  index_ = GridIndex(params_);
  cells_ = 1;
  for (int b : params_.bins) cells_ *= b;
  occupied_.assign(static_cast<std::size_t>(cells_), 0);
  objectives_.assign(static_cast<std::size_t>(cells_), 0);
  solutions_.resize(cells_, params_.solution_size);
  measures_.resize(cells_, dimensions());
  base_.resize(cells_, params_.base_feature_size);
}

AddStatus GridArchive::add(const Real* solution, Real objective, const Real* measures, const Real* base_features) {
  const Index cell = index_of(measures);
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
  if (params_.base_feature_size > 0 && base_features != nullptr)
    std::copy_n(base_features, params_.base_feature_size, base_.row(cell).data());
  return status;
}

void GridArchive::clear() {
  for (Index c : filled_) occupied_[static_cast<std::size_t>(c)] = 0;
  filled_.clear();
}

ArchiveStats GridArchive::stats() const {
  ArchiveStats s;
  s.num_elites = size();
  s.coverage = static_cast<double>(s.num_elites) / static_cast<double>(cells_);
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
  s.norm_qd_score = s.qd_score / static_cast<double>(cells_);
  return s;
}

void GridArchive::save(BinaryWriter& out) const {
  out.tag("grid_archive");
  out.value<std::int64_t>(cells_);
  out.value<std::int64_t>(params_.solution_size);
  out.value<std::int64_t>(params_.base_feature_size);
  out.value<std::int64_t>(dimensions());
  const auto n = static_cast<Index>(filled_.size());
  std::vector<std::int64_t> cells(filled_.begin(), filled_.end());
  std::vector<Real> objectives;
  RowMatrix solutions(n, params_.solution_size), measures(n, dimensions()), base(n, params_.base_feature_size);
  for (Index i = 0; i < n; ++i) {
    const Index c = filled_[static_cast<std::size_t>(i)];
    objectives.push_back(objectives_[static_cast<std::size_t>(c)]);
    solutions.row(i) = solutions_.row(c);
    measures.row(i) = measures_.row(c);
    base.row(i) = base_.row(c);
  }
  out.values(cells);
  out.values(objectives);
  out.matrix(solutions);
  out.matrix(measures);
  out.matrix(base);
}

void GridArchive::load(BinaryReader& in) {
  in.expect_tag("grid_archive");
  const auto cells = in.value<std::int64_t>("archive cells");
  const auto solution_size = in.value<std::int64_t>("archive solution size");
  const auto base_size = in.value<std::int64_t>("archive base-feature size");
  const auto dims = in.value<std::int64_t>("archive dimensions");
  if (cells != cells_ || solution_size != params_.solution_size || base_size != params_.base_feature_size ||
      dims != dimensions())
    in.fail(fmt::format("archive of {} cells ({} genes, {} base features, {} dimensions) does not fit this run's "
                        "archive of {} cells ({}, {}, {})",
                        cells, solution_size, base_size, dims, cells_, params_.solution_size,
                        params_.base_feature_size, dimensions()));
  const auto filled = in.values<std::int64_t>("archive cells filled");
  const auto objectives = in.values<Real>("archive objectives");
  RowMatrix solutions, measures, base;
  in.matrix(solutions, "archive solutions");
  in.matrix(measures, "archive measures");
  in.matrix(base, "archive base features");
  const auto n = static_cast<Index>(filled.size());
  if (static_cast<Index>(objectives.size()) != n || solutions.rows() != n || measures.rows() != n || base.rows() != n ||
      solutions.cols() != params_.solution_size || measures.cols() != dimensions() ||
      base.cols() != params_.base_feature_size)
    in.fail("archive contents disagree in size");
  clear();
  for (Index i = 0; i < n; ++i) {
    const auto c = static_cast<Index>(filled[static_cast<std::size_t>(i)]);
    if (c < 0 || c >= cells_ || occupied_[static_cast<std::size_t>(c)])
      in.fail(fmt::format("archive cell {} is out of range or repeated", c));
    occupied_[static_cast<std::size_t>(c)] = 1;
    objectives_[static_cast<std::size_t>(c)] = objectives[static_cast<std::size_t>(i)];
    solutions_.row(c) = solutions.row(i);
    measures_.row(c) = measures.row(i);
    base_.row(c) = base.row(i);
    filled_.push_back(c);
  }
}

}  // namespace qdmeta
