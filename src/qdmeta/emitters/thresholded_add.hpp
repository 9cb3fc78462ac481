#pragma once
// Adding a batch to an archive under CMA-MAE's thresholds (cell_thresholds.hpp): the archive
// stays the result archive (each cell keeps its best elite, replaced only by a better one), and
// the thresholds beside it, keyed by the archive's cell index, give each row the status and
// improvement value that the emitters rank by.
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <fmt/format.h>

#include "qdmeta/archive/archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/emitters/cell_thresholds.hpp"

namespace qdmeta {

// An archive of fixed cells whose cell of a measure vector can be asked (GridArchive, CvtArchive).
template <class A>
concept CellIndexedArchive = EliteArchive<A> && requires(const A& ca, const Real* measures) {
  { ca.index_of(measures) } -> std::convertible_to<Index>;
  { ca.clears() } -> std::convertible_to<std::uint64_t>;  // Scheduler resets its thresholds on a clear
};

// Adds the valid rows of `batch` to `archive` (its add_batch checks the batch first and throws
// InputError before anything changes), then offers the valid rows to `thresholds`: kSingle, each
// in order (CellThresholds::offer); kBatch, all against the thresholds before the batch
// (CellThresholds::offer_batch). `outcomes[r]` gets row r's outcome (an invalid row: kNotAdded,
// improvement -inf). The archive's elites are the same either way (each cell's best). Returns
// how many rows the thresholds accepted.
template <CellIndexedArchive A>
Index add_with_thresholds(A& archive, CellThresholds& thresholds, const EliteBatch& batch,
                          std::span<ThresholdOutcome> outcomes, AddMode mode = AddMode::kSingle) {
  if (thresholds.cells() != archive.cells()) {
    throw InputError(fmt::format("add_with_thresholds: the thresholds have {} cells, the archive {}",
                                 thresholds.cells(), archive.cells()));
  }
  if (static_cast<Index>(outcomes.size()) != batch.rows()) {
    throw InputError(fmt::format("add_with_thresholds: {} outcome slots for {} rows", outcomes.size(), batch.rows()));
  }
  archive.add_batch(batch);
  Index accepted = 0;
  if (mode == AddMode::kBatch) {
    std::vector<Index> cells(static_cast<std::size_t>(batch.rows()), 0);
    for (Index r = 0; r < batch.rows(); ++r)
      if (batch.is_valid(r)) cells[static_cast<std::size_t>(r)] = archive.index_of(batch.measures.row(r));
    thresholds.offer_batch(cells, batch.objectives, batch.valid, outcomes);
    for (const ThresholdOutcome& outcome : outcomes) accepted += outcome.status != AddStatus::kNotAdded;
    return accepted;
  }
  for (Index r = 0; r < batch.rows(); ++r) {
    ThresholdOutcome& outcome = outcomes[static_cast<std::size_t>(r)];
    if (!batch.is_valid(r)) {
      outcome = {AddStatus::kNotAdded, -std::numeric_limits<double>::infinity()};
      continue;
    }
    outcome = thresholds.offer(archive.index_of(batch.measures.row(r)), batch.objectives[static_cast<std::size_t>(r)]);
    accepted += outcome.status != AddStatus::kNotAdded;
  }
  return accepted;
}

}  // namespace qdmeta
