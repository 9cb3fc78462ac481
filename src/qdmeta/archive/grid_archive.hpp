#pragma once
// A MAP-Elites grid over N_t target features: equal-width bins per dimension, one elite per
// cell, replaced only by a strictly better objective. Cells are numbered in row-major (C)
// order, as pyribs's GridArchive. The elites live in an EliteStore (elite_store.hpp); the grid
// supplies the cell of a target-feature vector (GridIndex).
#include <cstdint>
#include <span>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/archive/elite_store.hpp"
#include "qdmeta/archive/grid_index.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct GridArchiveParams {
  std::vector<int> bins = {100, 100};  // bins per target dimension, each >= 1
  double lower = 0.0;                  // lower bound of every target feature
  double upper = 1.0;                  // upper bound of every target feature (> lower)
  // Per-target-feature bounds (pyribs's `ranges`), one per bin count; empty: lower and upper for all.
  std::vector<double> lower_bounds, upper_bounds;
  Index solution_size = 0;             // genes per solution, >= 1
  Index base_feature_size = 0;         // base features kept per elite (0: none)
  double qd_offset = 0.0;              // QD-score counts objective - qd_offset
  // Added before flooring, as pyribs does, so a value on a bin edge lands in the upper bin
  // despite float rounding (0.01f * 100 = 0.99999997); bins x FLT_EPSILON is added to it,
  // because float measures carry more rounding than pyribs's float64 (0.84f * 100 = 83.999997).
  double epsilon = 1e-6;
  void validate() const;
  double lower_of(std::size_t d) const { return lower_bounds.empty() ? lower : lower_bounds[d]; }
  double upper_of(std::size_t d) const { return upper_bounds.empty() ? upper : upper_bounds[d]; }
};

// The cells of a grid (the product of its bins), and what a GridArchive of `p` allocates for them
// (objective, occupied flag, solution, measures and base features per cell), in bytes, for a
// run's memory estimate (core/memory_estimate.hpp); p.solution_size and p.base_feature_size are
// used as they are, so set them first.
double grid_cells(const GridArchiveParams& p);
double grid_archive_bytes(const GridArchiveParams& p);

class GridArchive : private EliteStore {
 public:
  explicit GridArchive(GridArchiveParams params);

  const GridArchiveParams& params() const { return params_; }
  Index dimensions() const { return static_cast<Index>(params_.bins.size()); }
  using EliteStore::base_feature_size;
  using EliteStore::cells;
  using EliteStore::empty;
  using EliteStore::size;
  using EliteStore::solution_size;

  // Cell of a target-feature vector: floor((m - lower) / (upper - lower) * bins + epsilon),
  // clamped to [0, bins - 1] per dimension. Throws Error on NaN.
  Index index_of(const Real* measures) const { return index_.cell_of(measures); }
  // The same for whole feature-major blocks (grid_index.hpp).
  const GridIndex& grid_index() const { return index_; }
  void cells_of_t(const Real* measures_t, Index ld, Index count, std::int32_t* cells) const {
    index_.cells_of_t(measures_t, ld, count, cells);
  }

  // Adds the valid rows in batch order, the same as adding them one by one (of rows that tie
  // for a cell, the first keeps it); `status`, when given, gets every row's outcome (kNotAdded
  // for invalid rows). Returns how many rows entered. Throws InputError before adding anything
  // when the shapes do not fit or a valid row has a non-finite objective or measure.
  Index add_batch(const EliteBatch& batch, std::span<AddStatus> status = {});
  // One candidate, checked like a batch of one row.
  AddStatus add(std::span<const Real> solution, Real objective, std::span<const Real> measures,
                std::span<const Real> base_features = {});
  // Unchecked: `cell` must be index_of(measures) (for callers that bin whole blocks themselves,
  // as the map rebuild does).
  using EliteStore::place;
  using EliteStore::clear;
  using EliteStore::clears;

  using EliteStore::base_features;
  using EliteStore::filled_cells;
  using EliteStore::measures;
  using EliteStore::objective;
  using EliteStore::occupied;
  using EliteStore::sample_cell;
  using EliteStore::solution;
  using EliteStore::would_enter;

  using EliteStore::stats;
  // The elites sorted by cell, with base features when the archive keeps them.
  EliteTable elites() const { return elite_table(); }

  // Checkpoints: the filled cells in fill order with their contents. load() requires an
  // archive built with the same params and throws InputError otherwise.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  GridArchiveParams params_;
  GridIndex index_;
  // add_batch's scratch: the batch's measures feature-major, and their cells.
  std::vector<Real> measures_t_;
  std::vector<std::int32_t> batch_cells_;
};

}  // namespace qdmeta
