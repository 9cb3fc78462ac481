#pragma once
// A CVT-MAP-Elites archive (Vassiliades et al.; SPEC.md section 6): one cell per centroid, a
// descriptor belongs to the cell of its nearest centroid (exact, ties to the lowest index), one
// elite per cell, replaced only by a strictly better objective. Descriptors are the task's base
// features. Storage is struct-of-arrays, one row per cell, like GridArchive.
#include <cstdint>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct CvtArchiveParams {
  Index solution_size = 0;  // genes per solution, >= 1
  double qd_offset = 0.0;   // QD-score counts objective - qd_offset
  void validate() const;
};

class CvtArchive {
 public:
  // `centroids`: one row per cell (k x descriptor size).
  CvtArchive(CvtArchiveParams params, RowMatrix centroids);

  const CvtArchiveParams& params() const { return params_; }
  Index cells() const { return search_.count(); }
  Index dimensions() const { return search_.dimensions(); }
  Index size() const { return static_cast<Index>(filled_.size()); }
  bool empty() const { return filled_.empty(); }
  const RowMatrix& centroids() const { return search_.centroids(); }
  const NearestCentroid& search() const { return search_; }

  // The cell of a descriptor: a full search.
  Index index_of(const Real* measures) const { return search_.find(measures); }

  // Cells of `count` descriptors (row-major) into `cells`, and into `bounds` a lower bound on
  // the distance from each descriptor to every other centroid. With `parents` (the cell of each
  // row's parent elite, -1 for none), a row is first tried against its parent (offspring land
  // near their parent): with delta = |x - m_p| (m_p the parent's descriptor) and b_p the
  // parent's bound, every other centroid lies at least b_p - delta from x, so if x's distance to
  // the parent's centroid is below that, the parent's cell is x's nearest, exactly and without a
  // search. Other rows get the full search. The answer equals index_of's either way.
  // Single-threaded; callers may split the rows (each row's answer does not depend on it).
  void locate(const Real* measures, Index count, const Index* parents, Index* cells, double* bounds) const;

  AddStatus add(const Real* solution, Real objective, const Real* measures);
  // `cell` and `bound` must come from locate() for these measures (e.g. for a whole batch).
  AddStatus add_to_cell(Index cell, double bound, const Real* solution, Real objective, const Real* measures);
  void clear();

  bool occupied(Index cell) const { return occupied_[static_cast<std::size_t>(cell)] != 0; }
  Real objective(Index cell) const { return objectives_[static_cast<std::size_t>(cell)]; }
  const Real* solution(Index cell) const { return solutions_.row(cell).data(); }
  const Real* measures(Index cell) const { return measures_.row(cell).data(); }
  // Filled cells, in the order they were first filled.
  const std::vector<Index>& filled_cells() const { return filled_; }
  // A filled cell drawn uniformly. The archive must not be empty.
  Index sample_cell(Rng& rng) const { return filled_[rng.below(filled_.size())]; }

  ArchiveStats stats() const;

 private:
  CvtArchiveParams params_;
  NearestCentroid search_;
  std::vector<std::uint8_t> occupied_;
  std::vector<Real> objectives_;
  std::vector<double> bounds_;  // per elite: lower bound on its descriptor's distance to other centroids
  RowMatrix solutions_;
  RowMatrix measures_;
  std::vector<Index> filled_;
};

}  // namespace qdmeta
