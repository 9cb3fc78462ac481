#pragma once
// Rebuilding QD-Meta's archives from the database (docs/specification.md, QD-Meta): each
// of the lambda fresh maps is cleared, then every database row, oldest first, goes through the
// map's feature-map into its archive (as GridArchive::add_batch would, with solution = genotype,
// objective = fitness, measures = target features, and the base features when the archive keeps
// them). The code is written against BlockBinnedArchive (archive/archive.hpp); GridArchive is the
// one archive that models it.
//
// The result equals mapping and adding the rows one by one in age order, bit for bit, whatever
// the thread count: each archive receives its rows sequentially in age order, and a
// NeuralFeatureMap gives every row the same bits whatever block it is mapped in. The database
// is read in blocks of kRebuildBlockRows rows from its feature-major copy, shared by all the
// maps that one task handles while it is in cache; each map runs its network on it in registers
// (network_kernel.hpp), bins it in one vectorised pass (grid_index.hpp) and keeps each cell's
// winner. Maps are split into as many contiguous groups as the current
// task arena has threads (fix the thread count with tbb::task_arena or tbb::global_control);
// when they do not split evenly (one map on two threads), the database ranks are split
// instead, and each map's winners of the slices merge in rank order.
#include <span>

#include "qdmeta/archive/grid_archive.hpp"
#include "qdmeta/featuremap/neural_feature_map.hpp"
#include "qdmeta/meta/database.hpp"

namespace qdmeta {

inline constexpr Index kRebuildBlockRows = 512;
inline constexpr Index kRebuildChunkRows = 16 * kRebuildBlockRows;  // 8,192 rows, 655 KB of base features at N_b = 20

// Throws InputError when the spans differ in length, an entry is null, an archive appears
// twice, or sizes disagree: map inputs vs. database base features, map outputs vs. archive
// dimensions, archive solution size vs. database genotype size, archive base-feature size
// (0 or the database's).
void rebuild_archives(const Database& db, std::span<const NeuralFeatureMap* const> maps,
                      std::span<GridArchive* const> archives);

// One map, one archive, on the calling thread.
void rebuild_archive(const Database& db, const NeuralFeatureMap& map, GridArchive& archive);

}  // namespace qdmeta
