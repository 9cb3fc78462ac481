// SlidingBoundariesArchive's checkpoints: everything a later add() reads, so that a loaded
// archive remaps and places to the same bits as the original.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "qdmeta/archive/sliding_boundaries_archive.hpp"

namespace qdmeta {
namespace {

bool finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

}  // namespace

void SlidingBoundariesArchive::save(BinaryWriter& out) const {
  out.tag("sliding boundaries archive");
  out.value(static_cast<std::int64_t>(params_.solution_size));
  out.values(params_.dims);
  for (const auto& b : boundaries_) out.values(b);
  out.values(lower_);
  out.values(upper_);
  out.value(static_cast<std::int64_t>(buffer_.size()));
  for (const Entry& e : buffer_) {
    out.values(e.solution);
    out.value(e.objective);
    out.values(e.measures);
  }
  for (const auto& sorted : sorted_buffer_measures_) out.values(sorted);
  out.value(static_cast<std::int64_t>(total_added_));
  out.values(occupied_order_);
  for (const Index cell : occupied_order_) {
    const auto x = solution(cell);
    const auto at = measures(cell);
    out.values(std::vector<double>(x.begin(), x.end()));
    out.value(objective(cell));
    out.values(std::vector<double>(at.begin(), at.end()));
  }
}

void SlidingBoundariesArchive::load(BinaryReader& in) {
  in.expect_tag("sliding boundaries archive");
  const auto genes = in.value<std::int64_t>("sliding solution size");
  const auto dims = in.values<Index>("sliding dims");
  if (genes != params_.solution_size || dims != params_.dims)
    in.fail(fmt::format("the saved sliding-boundaries archive has {} genes and dims [{}]; this one {} and [{}]", genes,
                        fmt::join(dims, ", "), params_.solution_size, fmt::join(params_.dims, ", ")));
  const std::size_t m = dims.size();
  const auto genes_n = static_cast<std::size_t>(genes);
  std::vector<std::vector<double>> boundaries(m);
  for (std::size_t i = 0; i < m; ++i) {
    boundaries[i] = in.values<double>("sliding boundaries");
    if (boundaries[i].size() != static_cast<std::size_t>(dims[i]) + 1 || !finite(boundaries[i]))
      in.fail(fmt::format("the saved boundaries of measure {} are not {} finite values", i, dims[i] + 1));
  }
  auto lower = in.values<double>("sliding lower bounds");
  auto upper = in.values<double>("sliding upper bounds");
  if (lower.size() != m || upper.size() != m || !finite(lower) || !finite(upper))
    in.fail("the saved outer boundaries are not one finite pair per measure");
  const auto buffered = in.value<std::int64_t>("sliding buffer size");
  if (buffered < 0 || buffered > params_.buffer_capacity) in.fail(fmt::format("the saved buffer holds {} rows", buffered));
  std::deque<Entry> buffer;
  for (std::int64_t r = 0; r < buffered; ++r) {
    Entry e;
    e.solution = in.values<double>("buffered solution");
    e.objective = in.value<double>("buffered objective");
    e.measures = in.values<double>("buffered measures");
    if (e.solution.size() != genes_n || e.measures.size() != m || !finite(e.solution) || !finite(e.measures) ||
        !std::isfinite(e.objective))
      in.fail(fmt::format("buffered row {} does not fit the archive or is not finite", r));
    buffer.push_back(std::move(e));
  }
  std::vector<std::vector<double>> sorted(m);
  for (auto& s : sorted) {
    s = in.values<double>("sorted buffer measures");
    if (s.size() != buffer.size() || !std::is_sorted(s.begin(), s.end()))
      in.fail("the saved sorted measures do not fit the buffer");
  }
  const auto total = in.value<std::int64_t>("solutions added");
  if (total < 0) in.fail(fmt::format("the saved count of solutions added is {}", total));
  const auto order = in.values<Index>("filled cells");
  struct Elite {
    std::vector<double> solution, measures;
    double objective;
  };
  std::vector<Elite> elites;
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(cells_), 0);
  for (const Index cell : order) {
    if (cell < 0 || cell >= cells_ || seen[static_cast<std::size_t>(cell)])
      in.fail(fmt::format("saved cell {} is out of range or repeated", cell));
    seen[static_cast<std::size_t>(cell)] = 1;
    Elite e;
    e.solution = in.values<double>("elite solution");
    e.objective = in.value<double>("elite objective");
    e.measures = in.values<double>("elite measures");
    if (e.solution.size() != genes_n || e.measures.size() != m || !finite(e.solution) || !finite(e.measures) ||
        !std::isfinite(e.objective))
      in.fail(fmt::format("the elite of cell {} does not fit the archive or is not finite", cell));
    elites.push_back(std::move(e));
  }
  // All read and checked: now the archive changes.
  clear();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto c = static_cast<std::size_t>(order[k]);
    occupied_[c] = 1;
    occupied_order_.push_back(order[k]);
    std::copy(elites[k].solution.begin(), elites[k].solution.end(),
              solutions_.begin() + static_cast<std::ptrdiff_t>(c * genes_n));
    objectives_[c] = elites[k].objective;
    std::copy(elites[k].measures.begin(), elites[k].measures.end(),
              measures_.begin() + static_cast<std::ptrdiff_t>(c * m));
  }
  boundaries_ = std::move(boundaries);
  lower_ = std::move(lower);
  upper_ = std::move(upper);
  buffer_ = std::move(buffer);
  sorted_buffer_measures_ = std::move(sorted);
  total_added_ = static_cast<Index>(total);
}

}  // namespace qdmeta
