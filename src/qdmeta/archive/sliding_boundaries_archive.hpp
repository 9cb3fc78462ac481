#pragma once
// The sliding-boundaries archive of Fontaine et al. (2019), with pyribs's
// SlidingBoundariesArchive's rules: a grid whose boundaries start evenly spaced over the given
// ranges and, every `remap_frequency` solutions, move to the quantiles of the measures of the
// last `buffer_capacity` solutions; the archive's elites and the buffer are then added again
// (elites first, in the order their cells were first filled, then the buffer from oldest), so
// that cells follow where solutions actually lie. Solutions are added one at a time, in order,
// by MAP-Elites's rule (a new cell, or a strictly higher objective). Kept in double.
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct SlidingBoundariesParams {
  Index solution_size = 1;
  std::vector<Index> dims;                  // cells per measure, each >= 1
  std::vector<double> lower_bounds;         // one per measure, < upper
  std::vector<double> upper_bounds;
  double epsilon = 1e-6;                    // added to a measure before it is placed (pyribs's)
  Index remap_frequency = 100;              // >= 1
  Index buffer_capacity = 1000;             // >= 1
  double qd_offset = 0.0;
  // Throws InputError naming the first setting out of its range.
  void validate() const;
};

// One solution's fate, pyribs's codes: status 0 not added, 1 improved its cell, 2 filled a new
// one; value its objective minus the cell's before (0 for an empty cell).
struct SlidingAddResult {
  std::vector<std::uint8_t> status;
  std::vector<double> value;
};

class SlidingBoundariesArchive {
 public:
  explicit SlidingBoundariesArchive(const SlidingBoundariesParams& params);

  // Adds rows in order: solutions (n x solution_size), objectives (n), measures (n x measures).
  SlidingAddResult add(std::span<const double> solutions, std::span<const double> objectives,
                       std::span<const double> measures);
  // The cell of each row of `measures` (row-major grid index, the last measure fastest).
  std::vector<Index> index_of(std::span<const double> measures) const;

  Index measure_size() const { return static_cast<Index>(params_.dims.size()); }
  Index cells() const { return cells_; }
  const SlidingBoundariesParams& params() const { return params_; }
  // The boundaries of measure i: dims[i] + 1 values, cell j spans [b[j], b[j + 1]).
  const std::vector<double>& boundaries(Index measure) const { return boundaries_[static_cast<std::size_t>(measure)]; }
  // The elites, in the order their cells were first filled since the last remap.
  Index size() const { return static_cast<Index>(occupied_order_.size()); }
  std::vector<Index> elite_cells() const { return occupied_order_; }
  std::span<const double> solution(Index cell) const;
  double objective(Index cell) const { return objectives_[static_cast<std::size_t>(cell)]; }
  std::span<const double> measures(Index cell) const;
  ArchiveStats stats() const;

  // Checkpoints for bit-exact continuation (sliding_boundaries_checkpoint.cpp): boundaries,
  // buffer, elites and counts. load() requires an archive of the same solution size and dims
  // (InputError otherwise) and refuses a saved state that does not hold together.
  void save(BinaryWriter& out) const;
  void load(BinaryReader& in);

 private:
  struct Entry {
    std::vector<double> solution;
    double objective;
    std::vector<double> measures;
  };
  Index cell_of(const double* measures) const;
  // MAP-Elites's rule for one solution, the buffer untouched.
  std::pair<std::uint8_t, double> place(const double* solution, double objective, const double* measures);
  std::pair<std::uint8_t, double> remap();
  void clear();

  SlidingBoundariesParams params_;
  Index cells_ = 1;
  std::vector<std::vector<double>> boundaries_;
  std::vector<double> lower_, upper_;  // the outer boundaries in force
  std::deque<Entry> buffer_;
  std::vector<std::vector<double>> sorted_buffer_measures_;  // per measure, ascending
  Index total_added_ = 0;
  std::vector<std::uint8_t> occupied_;
  std::vector<Index> occupied_order_;
  std::vector<double> solutions_, objectives_, measures_;
};

}  // namespace qdmeta
