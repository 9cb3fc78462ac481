#pragma once
// A MAP-Elites grid over N_t target features: equal-width bins per dimension, one elite per
// cell, replaced only by a strictly better objective. Cells are numbered in row-major (C)
// order, as pyribs's GridArchive. Storage is struct-of-arrays, one row per cell.
#include <cstdint>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/grid_index.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct GridArchiveParams {
  std::vector<int> bins = {100, 100};  // bins per target dimension, each >= 1
  double lower = 0.0;                  // lower bound of every target feature
  double upper = 1.0;                  // upper bound of every target feature (> lower)
  Index solution_size = 0;             // genes per solution, >= 1
  Index base_feature_size = 0;         // base features kept per elite (0: none)
  double qd_offset = 0.0;              // QD-score counts objective - qd_offset
  // Added before flooring, as pyribs does, so a value on a bin edge lands in the upper bin
  // despite float rounding (0.01f * 100 = 0.99999997); bins x FLT_EPSILON is added to it,
  // because float measures carry more rounding than pyribs's float64 (0.84f * 100 = 83.999997).
  double epsilon = 1e-6;
  void validate() const;
};

enum class AddStatus : std::uint8_t { kNotAdded = 0, kImproved = 1, kNew = 2 };

class GridArchive {
 public:
  explicit GridArchive(GridArchiveParams params);

  const GridArchiveParams& params() const { return params_; }
  Index cells() const { return cells_; }
  Index dimensions() const { return static_cast<Index>(params_.bins.size()); }
  Index size() const { return static_cast<Index>(filled_.size()); }
  bool empty() const { return filled_.empty(); }

  // Cell of a target-feature vector: floor((m - lower) / (upper - lower) * bins + epsilon),
  // clamped to [0, bins - 1] per dimension. Throws Error on NaN.
  Index index_of(const Real* measures) const { return index_.cell_of(measures); }
  // The same for whole feature-major blocks (grid_index.hpp).
  const GridIndex& grid_index() const { return index_; }

  AddStatus add(const Real* solution, Real objective, const Real* measures, const Real* base_features = nullptr);
  void clear();

  bool occupied(Index cell) const { return occupied_[static_cast<std::size_t>(cell)] != 0; }
  Real objective(Index cell) const { return objectives_[static_cast<std::size_t>(cell)]; }
  const Real* solution(Index cell) const { return solutions_.row(cell).data(); }
  const Real* measures(Index cell) const { return measures_.row(cell).data(); }
  const Real* base_features(Index cell) const { return base_.row(cell).data(); }
  // Filled cells, in the order they were first filled.
  const std::vector<Index>& filled_cells() const { return filled_; }
  // A filled cell drawn uniformly. The archive must not be empty.
  Index sample_cell(Rng& rng) const { return filled_[rng.below(filled_.size())]; }

  ArchiveStats stats() const;

  // Checkpoints: the filled cells in fill order with their contents. load() requires an
  // archive built with the same params and throws InputError otherwise.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  GridArchiveParams params_;
  Index cells_ = 0;
  GridIndex index_;
  std::vector<std::uint8_t> occupied_;
  std::vector<Real> objectives_;
  RowMatrix solutions_;
  RowMatrix measures_;
  RowMatrix base_;
  std::vector<Index> filled_;
};

}  // namespace qdmeta
