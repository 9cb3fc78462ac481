#pragma once
// The cell of a target-feature vector in a GridArchive (grid_archive.hpp), one vector at a time
// or a whole feature-major block at once. The block version is what map rebuilds use: eight rows
// per step in AVX2 double lanes, no per-row branch, and the same arithmetic as the scalar one
// (float measures widened to double, (m - lower) * scale, then a fused multiply-add by the bin
// count with the margin, floor, clamp), so both give the same cell for every input.
#include <cstdint>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct GridArchiveParams;

class GridIndex {
 public:
  GridIndex() = default;
  // `params` must be valid (GridArchiveParams::validate()).
  explicit GridIndex(const GridArchiveParams& params);

  Index dimensions() const { return static_cast<Index>(bins_.size()); }

  // floor((m - lower) / (upper - lower) * bins + margin) clamped to [0, bins - 1] per
  // dimension, in row-major cell order. Throws Error on NaN.
  Index cell_of(const Real* measures) const;

  // cells[r] = cell_of(column r of measures_t) for r in [0, count), where measures_t is
  // dimensions() x ld row-major (feature-major: row d holds feature d of every row). Throws the
  // same Error as cell_of() when a column holds a NaN.
  void cells_of_t(const Real* measures_t, Index ld, Index count, std::int32_t* cells) const;

 private:
  std::vector<double> lower_;         // per target feature
  std::vector<double> scale_;         // 1 / (upper - lower), per target feature
  std::vector<double> bins_;          // per dimension, as double
  std::vector<double> top_;           // bins - 1
  std::vector<double> margin_;        // epsilon + bins * FLT_EPSILON (fused)
  std::vector<std::int32_t> stride_;  // row-major: the last dimension varies fastest
};

}  // namespace qdmeta
