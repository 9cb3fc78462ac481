#pragma once
// A CVT-MAP-Elites archive (Vassiliades et al.; docs/specification.md, CVT-MAP-Elites): one cell per centroid, a
// descriptor belongs to the cell of its nearest centroid (exact, ties to the lowest index), one
// elite per cell, replaced only by a strictly better objective. Descriptors are the task's base
// features.
//
// Offspring land near their parent, so each elite also keeps a neighbour list: the `neighbours`
// centroids nearest its descriptor with lower bounds on their distances (sorted), and a lower
// bound on its distance to every other centroid. An offspring x of parent p (descriptor m_p, delta = |x - m_p|) is at
// least d(m_p, c) - delta from any centroid c (triangle inequality): walking p's list in order
// of distance finds the nearest listed centroid, and when p's outside bound minus delta exceeds
// that distance no other centroid can be nearer, so the answer is exact without the full search
// over all centroids. Otherwise the full search runs. Both give index_of's answer.
// The elites live in an EliteStore (elite_store.hpp), with no base-feature columns.
#include <cstdint>
#include <span>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/centroid_values.hpp"
#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/archive/elite_store.hpp"
#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct CvtArchiveParams {
  Index solution_size = 0;  // genes per solution, >= 1
  double qd_offset = 0.0;   // QD-score counts objective - qd_offset
  Index neighbours = 256;   // neighbour list length per elite (capped at the cell count); 0: none
  void validate() const;
};

// Neighbour lists of descriptors about to enter the archive, one row each.
struct NeighbourLists {
  Eigen::Matrix<std::int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> cells;
  RowMatrix distances;
  std::vector<double> outside;
  // How far the descriptor may be from the point the distances were measured from: the true
  // distance to a listed centroid is at least the listed one minus this (and `outside` already
  // has it taken off). 0 for a list made from all centroids.
  std::vector<double> slack;
  void resize(Index rows, Index length) {
    cells.resize(rows, length);
    distances.resize(rows, length);
    outside.resize(static_cast<std::size_t>(rows));
    slack.resize(static_cast<std::size_t>(rows));
  }
};

// The centroid search, a base so that it is made (and allocates) before the elite store: with
// the store's arrays allocated first, the parent-bound search ran about 13% slower on the same
// work, from the heap layout alone (bench/README.md, "Issue 15").
struct CvtCentroidSearch {
  NearestCentroid search_;
};

class CvtArchive : private CvtCentroidSearch, private EliteStore {
 public:
  // `centroids`: one row per cell (k x descriptor size).
  CvtArchive(CvtArchiveParams params, RowMatrix centroids);

  const CvtArchiveParams& params() const { return params_; }
  Index dimensions() const { return search_.dimensions(); }
  using EliteStore::base_feature_size;  // 0: the measures are the base features
  using EliteStore::cells;
  using EliteStore::empty;
  using EliteStore::size;
  using EliteStore::solution_size;
  const RowMatrix& centroids() const { return search_.centroids(); }
  Index list_length() const { return list_length_; }

  // The cell of a descriptor: the full search.
  Index index_of(const Real* measures) const { return search_.find(measures); }

  // Cells of `count` descriptors (row-major) into `cells`. With `parents` (the cell of each
  // row's parent elite, -1 for none) and neighbour lists, rows are first settled from their
  // parent's list (see above); the others get the full search. Single-threaded; callers may
  // split the rows (each row's answer does not depend on it). Returns the number of rows that
  // needed the full search.
  // With `settled`, marks each row settled from its parent's list (1) or searched (0).
  Index locate(const Real* measures, Index count, const Index* parents, Index* cells,
               std::uint8_t* settled = nullptr) const;

  // The neighbour list of a descriptor into row `row` of `lists` (sized lists.resize(rows,
  // list_length())). With `parent` >= 0, a row that locate() settled from that parent's list:
  // the parent's list serves as it is, its slack and outside bound worn by delta (cheap), unless
  // that leaves too thin a margin; else the full computation (a pass over all centroids).
  void neighbours_of(const Real* measures, Index parent, NeighbourLists& lists, Index row) const;
  // neighbours_of in two steps, for batches: the parent's list into row `row` when it serves
  // (true; also when list_length() is 0), else false and the row is left for remake_lists.
  bool inherit_list(const Real* measures, Index parent, NeighbourLists& lists, Index row) const;
  // The lists of `count` descriptors (row-major) made from all centroids into rows rows[i] of
  // `lists`, kValueRows at a time (the same lists as one at a time, which is much slower).
  void remake_lists(const Real* measures, Index count, const Index* rows, NeighbourLists& lists) const;

  // Adds the valid rows in batch order, the same as adding them one by one (of rows that tie
  // for a cell, the first keeps it); `status`, when given, gets every row's outcome (kNotAdded
  // for invalid rows). With `parents` (one per row, -1 for none), cells are settled from the
  // parents' neighbour lists where they can be (the cell is the same either way). Returns how
  // many rows entered. Throws InputError before adding anything when the shapes do not fit or
  // a valid row has a non-finite objective or measure. Single-threaded; CvtMapElites splits the
  // same steps (locate, neighbours_of, add_to_cell) over the evaluator's workers.
  Index add_batch(const EliteBatch& batch, std::span<AddStatus> status = {}, const Index* parents = nullptr);
  // One candidate, checked like a batch of one row.
  AddStatus add(std::span<const Real> solution, Real objective, std::span<const Real> measures);
  // Unchecked: `cell` must be index_of(measures) and row `row` of `lists` its neighbour list
  // (ignored when list_length() is 0), computed beforehand (e.g. for a whole batch, in parallel).
  AddStatus add_to_cell(Index cell, const Real* solution, Real objective, const Real* measures,
                        const NeighbourLists& lists, Index row);
  using EliteStore::clear;
  using EliteStore::clears;

  using EliteStore::filled_cells;
  using EliteStore::measures;
  using EliteStore::objective;
  using EliteStore::occupied;
  using EliteStore::sample_cell;
  using EliteStore::solution;
  using EliteStore::would_enter;

  using EliteStore::stats;
  // index = centroid index, measures = descriptor (base features), no base-feature columns.
  EliteTable elites() const { return elite_table(); }

  // Checkpoints: the elites in fill order. load() re-adds them to an archive with the same
  // centroids, so cells are found again (and must agree) and neighbour lists are made afresh:
  // lists only decide which centroids get the exact check, never the cell.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  // The nearest centroid from the parent's list, or -1 when the list cannot prove it.
  Index from_parent(const Real* x, Index parent) const;
  // Start the loads a walk from `parent` needs: its list and descriptor, then (once the list
  // has arrived) the first listed centroid rows.
  void prefetch_list(Index parent) const;
  void prefetch_rows(Index parent) const;

  CvtArchiveParams params_;
  Index list_length_ = 0;
  NeighbourLists lists_;  // one row per cell: its elite's neighbour list
  // add_batch's scratch.
  std::vector<Index> batch_cells_;
  std::vector<std::uint8_t> batch_settled_;
  RowMatrix batch_measures_;
  NeighbourLists batch_list_;
};

}  // namespace qdmeta
