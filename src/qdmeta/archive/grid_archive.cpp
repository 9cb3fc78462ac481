#include "qdmeta/archive/grid_archive.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

namespace {
// One feature's [lower, upper]: finite, ordered, and of a width whose reciprocal is finite.
void check_range(double lower, double upper) {
  if (!(lower < upper) || !std::isfinite(lower) || !std::isfinite(upper))
    throw InputError(fmt::format("archive range [{}, {}] is invalid: lower must be below upper", lower, upper));
  // Cells come from (m - lower) * (1 / width): a width whose reciprocal overflows (below the
  // smallest normal double) makes that infinite, and 0 * inf a NaN cell; one that overflows
  // itself makes every cell 0.
  const double width = upper - lower;
  if (!std::isfinite(width))
    throw InputError(fmt::format("archive range [{}, {}] is too wide: upper - lower overflows a double", lower, upper));
  if (width < std::numeric_limits<double>::min())
    throw InputError(fmt::format("archive range [{}, {}] is too narrow: upper - lower = {} is below {}, the smallest "
                                 "normal double",
                                 lower, upper, width, std::numeric_limits<double>::min()));
}
}  // namespace

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
  check_range(lower, upper);
  if (lower_bounds.size() != upper_bounds.size() || (!lower_bounds.empty() && lower_bounds.size() != bins.size()))
    throw InputError(fmt::format("archive ranges: {} lower and {} upper bounds for {} target features: give one "
                                 "(lower, upper) pair per feature",
                                 lower_bounds.size(), upper_bounds.size(), bins.size()));
  for (std::size_t d = 0; d < lower_bounds.size(); ++d) check_range(lower_bounds[d], upper_bounds[d]);
  require_at_least("archive solution size", solution_size, Index{1});
  require_at_least("archive base-feature size", base_feature_size, Index{0});
  require_range("archive.epsilon", epsilon, 0.0, 0.5);
}

namespace {
EliteStoreShape store_shape(const GridArchiveParams& p) {
  p.validate();
  Index cells = 1;
  for (int b : p.bins) cells *= b;
  return {cells, p.solution_size, static_cast<Index>(p.bins.size()), p.base_feature_size, p.qd_offset};
}
}  // namespace

double grid_cells(const GridArchiveParams& p) {
  double cells = 1;
  for (int b : p.bins) cells *= static_cast<double>(b);
  return cells;
}

double grid_archive_bytes(const GridArchiveParams& p) {
  const auto per_cell = static_cast<double>(sizeof(Real) + 1 +
                                            sizeof(Real) * static_cast<std::size_t>(p.solution_size +
                                                                                    static_cast<Index>(p.bins.size()) +
                                                                                    p.base_feature_size));
  return grid_cells(p) * per_cell;
}

GridArchive::GridArchive(GridArchiveParams params)
    : EliteStore(store_shape(params)), params_(std::move(params)), index_(params_) {}

Index GridArchive::add_batch(const EliteBatch& batch, std::span<AddStatus> status) {
  const Index dims = dimensions();
  check_batch(batch, status.size(), solution_size(), dims, base_feature_size(), "grid archive");
  const Index rows = batch.rows();
  // Cells of the whole block in one vectorised pass; invalid rows (whose measures a task may
  // leave undefined) get a cell that is never used.
  measures_t_.resize(static_cast<std::size_t>(dims * rows));
  batch_cells_.resize(static_cast<std::size_t>(rows));
  for (Index r = 0; r < rows; ++r) {
    const Real* m = batch.measures.row(r);
    const bool valid = batch.is_valid(r);
    for (Index d = 0; d < dims; ++d) measures_t_[static_cast<std::size_t>(d * rows + r)] = valid ? m[d] : Real{0};
  }
  index_.cells_of_t(measures_t_.data(), rows, rows, batch_cells_.data());
  const bool keep_base = base_feature_size() > 0;
  Index added = 0;
  for (Index r = 0; r < rows; ++r) {
    AddStatus s = AddStatus::kNotAdded;
    if (batch.is_valid(r))
      s = place(batch_cells_[static_cast<std::size_t>(r)], batch.solutions.row(r),
                batch.objectives[static_cast<std::size_t>(r)], batch.measures.row(r),
                keep_base ? batch.base_features.row(r) : nullptr);
    added += s != AddStatus::kNotAdded;
    if (!status.empty()) status[static_cast<std::size_t>(r)] = s;
  }
  return added;
}

AddStatus GridArchive::add(std::span<const Real> solution, Real objective, std::span<const Real> measures,
                           std::span<const Real> base_features) {
  const auto width = [](std::span<const Real> s) { return static_cast<Index>(s.size()); };
  EliteBatch one{{solution.data(), 1, width(solution)},
                 {&objective, 1},
                 {measures.data(), 1, width(measures)},
                 base_features.empty() ? RowsView{} : RowsView{base_features.data(), 1, width(base_features)},
                 {}};
  AddStatus status;
  add_batch(one, {&status, 1});
  return status;
}

void GridArchive::save(BinaryWriter& out) const {
  out.tag("grid_archive");
  out.value<std::int64_t>(cells());
  out.value<std::int64_t>(params_.solution_size);
  out.value<std::int64_t>(params_.base_feature_size);
  out.value<std::int64_t>(dimensions());
  save_elites(out, true);
}

void GridArchive::load(BinaryReader& in) {
  in.expect_tag("grid_archive");
  const auto cells = in.value<std::int64_t>("archive cells");
  const auto solution_size = in.value<std::int64_t>("archive solution size");
  const auto base_size = in.value<std::int64_t>("archive base-feature size");
  const auto dims = in.value<std::int64_t>("archive dimensions");
  if (cells != this->cells() || solution_size != params_.solution_size || base_size != params_.base_feature_size ||
      dims != dimensions())
    in.fail(fmt::format("archive of {} cells ({} genes, {} base features, {} dimensions) does not fit this run's "
                        "archive of {} cells ({}, {}, {})",
                        cells, solution_size, base_size, dims, this->cells(), params_.solution_size,
                        params_.base_feature_size, dimensions()));
  restore(read_elites(in, true, "archive"), in);
}

}  // namespace qdmeta
