#pragma once
// The storage every cell-based archive shares (GridArchive, CvtArchive): one elite per cell,
// its fields in contiguous struct-of-arrays rows (objective, solution, measures, base features),
// occupancy flags and the filled cells in the order they were first filled. A candidate enters
// an empty cell, or replaces the elite of a full one when its objective is strictly better.
// The archives on top supply only how a descriptor maps to a cell.
#include <cstdint>
#include <string_view>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct EliteStoreShape {
  Index cells = 0;
  Index solution_size = 0;
  Index measure_size = 0;
  Index base_feature_size = 0;  // 0: none kept
  double qd_offset = 0.0;       // QD-score counts objective - qd_offset
};

// Elites read back from a checkpoint, in fill order, their sizes checked against the store.
struct SavedElites {
  std::vector<std::int64_t> cells;
  std::vector<Real> objectives;
  RowMatrix solutions;
  RowMatrix measures;
  RowMatrix base_features;
  Index size() const { return static_cast<Index>(cells.size()); }
};

class EliteStore {
 public:
  EliteStore() = default;
  explicit EliteStore(const EliteStoreShape& shape);

  Index cells() const { return shape_.cells; }
  Index size() const { return static_cast<Index>(filled_.size()); }
  bool empty() const { return filled_.empty(); }
  Index solution_size() const { return shape_.solution_size; }
  Index measure_size() const { return shape_.measure_size; }
  Index base_feature_size() const { return shape_.base_feature_size; }
  double qd_offset() const { return shape_.qd_offset; }

  bool occupied(Index cell) const { return occupied_[static_cast<std::size_t>(cell)] != 0; }
  Real objective(Index cell) const { return objectives_[static_cast<std::size_t>(cell)]; }
  const Real* solution(Index cell) const { return solutions_.row(cell).data(); }
  const Real* measures(Index cell) const { return measures_.row(cell).data(); }
  const Real* base_features(Index cell) const { return base_.row(cell).data(); }
  // Filled cells, in the order they were first filled.
  const std::vector<Index>& filled_cells() const { return filled_; }
  // A filled cell drawn uniformly. The store must not be empty.
  Index sample_cell(Rng& rng) const { return filled_[rng.below(filled_.size())]; }
  // True when `objective` would enter `cell` now (empty, or strictly better).
  bool would_enter(Index cell, Real objective) const { return !occupied(cell) || objective > this->objective(cell); }

  // Puts a candidate in `cell` (its archive's cell for `measures`) unless the elite there is at
  // least as good. No checks: callers check whole batches first (check_batch). `base_features`
  // is read only when the store keeps them.
  AddStatus place(Index cell, const Real* solution, Real objective, const Real* measures, const Real* base_features) {
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
    store(cell, solution, objective, measures, base_features);
    return status;
  }
  // Empties every cell (the storage stays allocated) and counts the clear.
  void clear();
  // How many times clear() has emptied the store (loading a checkpoint does not count): what
  // holds per-cell state beside the archive (a Scheduler's thresholds) resets when it changes.
  std::uint64_t clears() const { return clears_; }

  // Over the filled cells in fill order; coverage over cells().
  ArchiveStats stats() const;
  // The elites sorted by cell, base-feature columns when the store keeps them.
  EliteTable elite_table() const;

  // Checkpoints: the filled cells in fill order, then their objectives, solutions, measures and
  // (with_base) base features. `label` names the fields in read errors ("archive", "CVT").
  void save_elites(BinaryWriter& out, bool with_base) const;
  SavedElites read_elites(BinaryReader& in, bool with_base, std::string_view label) const;
  // Empties the store (not counted as a clear) and puts saved elites back in their cells, in order; fails `in` on a cell
  // out of range or repeated.
  void restore(const SavedElites& saved, const BinaryReader& in);

 protected:
  // Empties every cell without counting a clear (a checkpoint's restore).
  void remove_all();

 private:
  void store(Index cell, const Real* solution, Real objective, const Real* measures, const Real* base_features);

  EliteStoreShape shape_;
  std::vector<std::uint8_t> occupied_;
  std::vector<Real> objectives_;
  RowMatrix solutions_;
  RowMatrix measures_;
  RowMatrix base_;
  std::vector<Index> filled_;
  std::uint64_t clears_ = 0;
};

}  // namespace qdmeta
