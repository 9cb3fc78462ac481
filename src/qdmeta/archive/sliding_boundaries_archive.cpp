#include "qdmeta/archive/sliding_boundaries_archive.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError("SlidingBoundariesArchive: " + what);
}

}  // namespace

void SlidingBoundariesParams::validate() const {
  require(solution_size >= 1, fmt::format("solution_dim ({}) must be at least 1", solution_size));
  require(!dims.empty(), "dims is empty: give the number of cells of each measure");
  require(lower_bounds.size() == dims.size() && upper_bounds.size() == dims.size(),
          fmt::format("ranges has {} pairs, dims {} measures: give one (lower, upper) per measure",
                      lower_bounds.size(), dims.size()));
  for (std::size_t i = 0; i < dims.size(); ++i) {
    require(dims[i] >= 1, fmt::format("dims[{}] ({}) must be at least 1", i, dims[i]));
    require(std::isfinite(lower_bounds[i]) && std::isfinite(upper_bounds[i]) && lower_bounds[i] < upper_bounds[i],
            fmt::format("ranges[{}] ({}, {}) must be finite with lower < upper", i, lower_bounds[i], upper_bounds[i]));
  }
  require(std::isfinite(epsilon) && epsilon >= 0.0, fmt::format("epsilon ({}) must be finite and >= 0", epsilon));
  require(remap_frequency >= 1, fmt::format("remap_frequency ({}) must be at least 1", remap_frequency));
  require(buffer_capacity >= 1, fmt::format("buffer_capacity ({}) must be at least 1", buffer_capacity));
  require(std::isfinite(qd_offset), "qd_score_offset must be finite");
}

SlidingBoundariesArchive::SlidingBoundariesArchive(const SlidingBoundariesParams& params)
    : params_(params), lower_(params.lower_bounds), upper_(params.upper_bounds) {
  params_.validate();
  for (Index d : params_.dims) cells_ *= d;
  const auto m = params_.dims.size();
  boundaries_.resize(m);
  sorted_buffer_measures_.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    // Evenly spaced, as numpy.linspace(lower, upper, dims + 1): i * step + lower, the end exact.
    const auto n = static_cast<std::size_t>(params_.dims[i]);
    const double step = (upper_[i] - lower_[i]) / static_cast<double>(n);
    boundaries_[i].resize(n + 1);
    for (std::size_t j = 0; j < n; ++j) boundaries_[i][j] = static_cast<double>(j) * step + lower_[i];
    boundaries_[i][n] = upper_[i];
  }
  const auto cells = static_cast<std::size_t>(cells_);
  occupied_.assign(cells, 0);
  objectives_.assign(cells, 0.0);
  solutions_.assign(cells * static_cast<std::size_t>(params_.solution_size), 0.0);
  measures_.assign(cells * m, 0.0);
}

Index SlidingBoundariesArchive::cell_of(const double* measures) const {
  Index cell = 0;
  for (std::size_t i = 0; i < params_.dims.size(); ++i) {
    const double at = std::min(std::max(measures[i] + params_.epsilon, lower_[i]), upper_[i] - params_.epsilon);
    const auto& b = boundaries_[i];
    const auto dim = params_.dims[i];
    // The first of the cells' lower boundaries that is >= the measure, less one, at least 0.
    const Index above = std::lower_bound(b.begin(), b.begin() + dim, at) - b.begin();
    cell = cell * dim + std::max<Index>(0, above - 1);
  }
  return cell;
}

std::vector<Index> SlidingBoundariesArchive::index_of(std::span<const double> measures) const {
  const auto m = params_.dims.size();
  require(measures.size() % m == 0, fmt::format("measures has {} values, not n x {} measures", measures.size(), m));
  std::vector<Index> cells(measures.size() / m);
  for (std::size_t r = 0; r < cells.size(); ++r) cells[r] = cell_of(measures.data() + r * m);
  return cells;
}

std::span<const double> SlidingBoundariesArchive::solution(Index cell) const {
  const auto s = static_cast<std::size_t>(params_.solution_size);
  return {solutions_.data() + static_cast<std::size_t>(cell) * s, s};
}

std::span<const double> SlidingBoundariesArchive::measures(Index cell) const {
  const auto m = params_.dims.size();
  return {measures_.data() + static_cast<std::size_t>(cell) * m, m};
}

std::pair<std::uint8_t, double> SlidingBoundariesArchive::place(const double* solution, double objective,
                                                                const double* measures) {
  const auto cell = static_cast<std::size_t>(cell_of(measures));
  const bool occupied = occupied_[cell] != 0;
  const double before = occupied ? objectives_[cell] : 0.0;
  if (occupied && !(objective > before)) return {0, objective - before};
  if (!occupied) {
    occupied_[cell] = 1;
    occupied_order_.push_back(static_cast<Index>(cell));
  }
  const auto s = static_cast<std::size_t>(params_.solution_size);
  const auto m = params_.dims.size();
  std::copy(solution, solution + s, solutions_.begin() + static_cast<std::ptrdiff_t>(cell * s));
  std::copy(measures, measures + m, measures_.begin() + static_cast<std::ptrdiff_t>(cell * m));
  objectives_[cell] = objective;
  return {occupied ? std::uint8_t{1} : std::uint8_t{2}, objective - before};
}

void SlidingBoundariesArchive::clear() {
  for (Index cell : occupied_order_) occupied_[static_cast<std::size_t>(cell)] = 0;
  occupied_order_.clear();
}

std::pair<std::uint8_t, double> SlidingBoundariesArchive::remap() {
  const std::size_t size = buffer_.size();
  for (std::size_t i = 0; i < params_.dims.size(); ++i) {
    const auto dim = static_cast<std::size_t>(params_.dims[i]);
    const auto& sorted = sorted_buffer_measures_[i];
    for (std::size_t j = 0; j < dim; ++j) boundaries_[i][j] = sorted[j * size / dim];
    boundaries_[i][dim] = sorted.back();
  }
  // The elites, then the buffer but its last entry, then that one (whose fate add() reports).
  std::vector<Entry> again;
  again.reserve(occupied_order_.size() + size);
  for (Index cell : occupied_order_) {
    const auto x = solution(cell);
    const auto at = measures(cell);
    again.push_back({{x.begin(), x.end()}, objective(cell), {at.begin(), at.end()}});
  }
  again.insert(again.end(), buffer_.begin(), buffer_.end());
  clear();
  std::pair<std::uint8_t, double> last{0, 0.0};
  for (const Entry& e : again) last = place(e.solution.data(), e.objective, e.measures.data());
  // As pyribs, the outer bounds that clip measures follow the new boundaries only after the
  // solutions are added again.
  for (std::size_t i = 0; i < params_.dims.size(); ++i) {
    lower_[i] = boundaries_[i].front();
    upper_[i] = boundaries_[i][static_cast<std::size_t>(params_.dims[i])];
  }
  return last;
}

SlidingAddResult SlidingBoundariesArchive::add(std::span<const double> solutions, std::span<const double> objectives,
                                               std::span<const double> measures) {
  const std::size_t rows = objectives.size();
  const auto s = static_cast<std::size_t>(params_.solution_size);
  const auto m = params_.dims.size();
  require(solutions.size() == rows * s,
          fmt::format("solution has {} values, not {} rows x solution_dim ({})", solutions.size(), rows, s));
  require(measures.size() == rows * m,
          fmt::format("measures has {} values, not {} rows x {} measures", measures.size(), rows, m));
  require(std::all_of(objectives.begin(), objectives.end(), [](double f) { return std::isfinite(f); }),
          "objective must be finite");
  require(std::all_of(measures.begin(), measures.end(), [](double v) { return std::isfinite(v); }),
          "measures must be finite");
  SlidingAddResult result;
  result.status.resize(rows);
  result.value.resize(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    const double* x = solutions.data() + r * s;
    const double* at = measures.data() + r * m;
    if (buffer_.size() == static_cast<std::size_t>(params_.buffer_capacity)) {
      for (std::size_t i = 0; i < m; ++i) {
        auto& sorted = sorted_buffer_measures_[i];
        sorted.erase(std::lower_bound(sorted.begin(), sorted.end(), buffer_.front().measures[i]));
      }
      buffer_.pop_front();
    }
    buffer_.push_back({{x, x + s}, objectives[r], {at, at + m}});
    for (std::size_t i = 0; i < m; ++i) {
      auto& sorted = sorted_buffer_measures_[i];
      sorted.insert(std::upper_bound(sorted.begin(), sorted.end(), at[i]), at[i]);
    }
    ++total_added_;
    const auto [status, value] =
        total_added_ % params_.remap_frequency == 0 ? remap() : place(x, objectives[r], at);
    result.status[r] = status;
    result.value[r] = value;
  }
  return result;
}

ArchiveStats SlidingBoundariesArchive::stats() const {
  return archive_stats(
      [&](auto&& visit) {
        for (Index cell : occupied_order_) visit(objective(cell));
      },
      static_cast<double>(cells_), params_.qd_offset);
}

}  // namespace qdmeta
