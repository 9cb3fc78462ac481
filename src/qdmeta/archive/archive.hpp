#pragma once
// What the algorithms need of an archive, as concepts (resolved at compile time, so the hot
// loops call the archive's members directly). GridArchive and CvtArchive model EliteArchive;
// GridArchive also models BlockBinnedArchive, which the map rebuild needs.
#include <concepts>
#include <cstdint>
#include <span>

#include "qdmeta/archive/archive_stats.hpp"
#include "qdmeta/archive/elite_batch.hpp"
#include "qdmeta/archive/elite_table.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

// Cells holding one elite each: batch add, uniform parent selection, statistics, the elite
// table and checkpoints.
template <class A>
concept EliteArchive = requires(A& a, const A& ca, const EliteBatch& batch, std::span<AddStatus> status, Rng& rng,
                                Index cell, BinaryWriter& out, BinaryReader& in) {
  { ca.cells() } -> std::convertible_to<Index>;
  { ca.dimensions() } -> std::convertible_to<Index>;
  { ca.size() } -> std::convertible_to<Index>;
  { ca.empty() } -> std::convertible_to<bool>;
  { ca.solution_size() } -> std::convertible_to<Index>;
  { ca.base_feature_size() } -> std::convertible_to<Index>;
  { ca.sample_cell(rng) } -> std::convertible_to<Index>;
  { ca.solution(cell) } -> std::convertible_to<const Real*>;
  { ca.objective(cell) } -> std::convertible_to<Real>;
  { ca.filled_cells() } -> std::convertible_to<const std::vector<Index>&>;
  { ca.stats() } -> std::same_as<ArchiveStats>;
  { ca.elites() } -> std::same_as<EliteTable>;
  { a.add_batch(batch, status) } -> std::convertible_to<Index>;
  a.clear();
  ca.save(out);
  a.load(in);
};

// An archive whose cells can be found for a whole feature-major block of measures at once and
// that takes candidates whose cell the caller found (the map rebuild keeps each cell's winner
// itself, then places it).
template <class A>
concept BlockBinnedArchive =
    EliteArchive<A> && requires(A& a, const A& ca, const Real* measures_t, std::int32_t* cells, const Real* row) {
      ca.cells_of_t(measures_t, Index{}, Index{}, cells);
      { a.place(Index{}, row, Real{}, row, row) } -> std::same_as<AddStatus>;
    };

}  // namespace qdmeta
