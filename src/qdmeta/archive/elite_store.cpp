#include "qdmeta/archive/elite_store.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/copy_row.hpp"

namespace qdmeta {

EliteStore::EliteStore(const EliteStoreShape& shape) : shape_(shape) {
  occupied_.assign(static_cast<std::size_t>(shape_.cells), 0);
  objectives_.assign(static_cast<std::size_t>(shape_.cells), 0);
  solutions_.resize(shape_.cells, shape_.solution_size);
  measures_.resize(shape_.cells, shape_.measure_size);
  base_.resize(shape_.cells, shape_.base_feature_size);
}

void EliteStore::store(Index cell, const Real* solution, Real objective, const Real* measures,
                       const Real* base_features) {
  objectives_[static_cast<std::size_t>(cell)] = objective;
  copy_row(solution, shape_.solution_size, solutions_.row(cell).data());
  copy_row(measures, shape_.measure_size, measures_.row(cell).data());
  if (shape_.base_feature_size > 0 && base_features != nullptr)
    std::copy_n(base_features, shape_.base_feature_size, base_.row(cell).data());
}

void EliteStore::clear() {
  remove_all();
  ++clears_;
}

void EliteStore::remove_all() {
  for (Index c : filled_) occupied_[static_cast<std::size_t>(c)] = 0;
  filled_.clear();
}

ArchiveStats EliteStore::stats() const {
  return archive_stats(
      [&](auto&& visit) {
        for (Index c : filled_) visit(static_cast<double>(objectives_[static_cast<std::size_t>(c)]));
      },
      static_cast<double>(shape_.cells), shape_.qd_offset);
}

EliteTable EliteStore::elite_table() const {
  EliteTable t;
  std::vector<Index> cells = filled_;
  std::sort(cells.begin(), cells.end());
  const auto count = static_cast<Index>(cells.size());
  t.index.assign(cells.begin(), cells.end());
  t.objective.resize(cells.size());
  t.measures.resize(count, shape_.measure_size);
  t.solutions.resize(count, shape_.solution_size);
  t.base_features.resize(count, shape_.base_feature_size);
  for (Index i = 0; i < count; ++i) {
    const Index c = cells[static_cast<std::size_t>(i)];
    t.objective[static_cast<std::size_t>(i)] = objective(c);
    t.measures.row(i) = measures_.row(c);
    t.solutions.row(i) = solutions_.row(c);
    t.base_features.row(i) = base_.row(c);
  }
  return t;
}

void EliteStore::save_elites(BinaryWriter& out, bool with_base) const {
  const auto n = static_cast<Index>(filled_.size());
  std::vector<std::int64_t> cells(filled_.begin(), filled_.end());
  std::vector<Real> objectives;
  objectives.reserve(filled_.size());
  RowMatrix solutions(n, shape_.solution_size), measures(n, shape_.measure_size);
  RowMatrix base(with_base ? n : 0, shape_.base_feature_size);
  for (Index i = 0; i < n; ++i) {
    const Index c = filled_[static_cast<std::size_t>(i)];
    objectives.push_back(objectives_[static_cast<std::size_t>(c)]);
    solutions.row(i) = solutions_.row(c);
    measures.row(i) = measures_.row(c);
    if (with_base) base.row(i) = base_.row(c);
  }
  out.values(cells);
  out.values(objectives);
  out.matrix(solutions);
  out.matrix(measures);
  if (with_base) out.matrix(base);
}

SavedElites EliteStore::read_elites(BinaryReader& in, bool with_base, std::string_view label) const {
  SavedElites s;
  s.cells = in.values<std::int64_t>(fmt::format("{} cells filled", label));
  s.objectives = in.values<Real>(fmt::format("{} objectives", label));
  in.matrix(s.solutions, fmt::format("{} solutions", label));
  in.matrix(s.measures, fmt::format("{} measures", label));
  if (with_base) in.matrix(s.base_features, fmt::format("{} base features", label));
  const Index n = s.size();
  const bool base_fits = !with_base || (s.base_features.rows() == n && s.base_features.cols() == shape_.base_feature_size);
  if (static_cast<Index>(s.objectives.size()) != n || s.solutions.rows() != n || s.measures.rows() != n || !base_fits ||
      s.solutions.cols() != shape_.solution_size || s.measures.cols() != shape_.measure_size)
    in.fail(fmt::format("{} contents disagree in size", label == "archive" ? "archive" : fmt::format("{} archive", label)));
  // As add() requires of every elite: a saved state whose bytes were changed must not load a NaN.
  for (Index i = 0; i < n; ++i)
    if (!std::isfinite(s.objectives[static_cast<std::size_t>(i)]) || !s.measures.row(i).allFinite())
      in.fail(fmt::format("{} elite {} has a non-finite objective or measure: the saved state is damaged", label, i));
  return s;
}

void EliteStore::restore(const SavedElites& saved, const BinaryReader& in) {
  remove_all();
  const bool with_base = saved.base_features.rows() == saved.size() && shape_.base_feature_size > 0;
  for (Index i = 0; i < saved.size(); ++i) {
    const auto c = static_cast<Index>(saved.cells[static_cast<std::size_t>(i)]);
    if (c < 0 || c >= shape_.cells || occupied(c)) in.fail(fmt::format("archive cell {} is out of range or repeated", c));
    occupied_[static_cast<std::size_t>(c)] = 1;
    filled_.push_back(c);
    store(c, saved.solutions.row(i).data(), saved.objectives[static_cast<std::size_t>(i)], saved.measures.row(i).data(),
          with_base ? saved.base_features.row(i).data() : nullptr);
  }
}

}  // namespace qdmeta
