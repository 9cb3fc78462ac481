#include "qdmeta/meta/rebuild.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "qdmeta/archive/archive.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/featuremap/network_kernel.hpp"

namespace qdmeta {
namespace {

template <BlockBinnedArchive Archive>
void check(const Database& db, std::span<const NeuralFeatureMap* const> maps, std::span<Archive* const> archives) {
  if (maps.size() != archives.size())
    throw InputError(fmt::format("rebuild: {} feature-maps but {} archives", maps.size(), archives.size()));
  // Cell winners keep their database rank in 32 bits.
  if (db.capacity() > std::numeric_limits<std::int32_t>::max())
    throw InputError(fmt::format("rebuild: a database of {} rows is beyond the 2^31 - 1 a rebuild can index", db.capacity()));
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr) throw InputError(fmt::format("rebuild: feature-map {} is null", i));
    if (archives[i] == nullptr) throw InputError(fmt::format("rebuild: archive {} is null", i));
    const NeuralFeatureMap& map = *maps[i];
    const Archive& archive = *archives[i];
    if (map.input_size() != db.base_feature_size())
      throw InputError(fmt::format("rebuild: feature-map {} reads {} base features but the database stores {}", i,
                                   map.input_size(), db.base_feature_size()));
    if (map.output_size() != archive.dimensions())
      throw InputError(fmt::format("rebuild: feature-map {} gives {} target features but archive {} has {} dimensions",
                                   i, map.output_size(), i, archive.dimensions()));
    if (archive.solution_size() != db.genotype_size())
      throw InputError(fmt::format("rebuild: archive {} stores solutions of {} genes but the database stores {}", i,
                                   archive.solution_size(), db.genotype_size()));
    const Index keep = archive.base_feature_size();
    if (keep != 0 && keep != db.base_feature_size())
      throw InputError(fmt::format("rebuild: archive {} keeps {} base features but the database stores {}", i, keep,
                                   db.base_feature_size()));
    for (std::size_t j = 0; j < i; ++j)
      if (archives[j] == archives[i]) throw InputError(fmt::format("rebuild: archives {} and {} are the same", j, i));
  }
}

// Asks for the cache lines of a row of `count` floats.
inline void prefetch_row(const Real* row, Index count) {
  for (Index i = 0; i < count; i += 64 / static_cast<Index>(sizeof(Real))) __builtin_prefetch(row + i);
  __builtin_prefetch(row + count - 1);
}

// The winner of each cell while the database streams by: the first row with the highest
// fitness, exactly the elite that inserting row by row would leave (replacement only when
// strictly better). Rows are copied into the archive once per cell at the end, not at every
// improvement: in a real run newer rows are usually better, so that saves most of the copying.
struct CellWinners {
  // A cell's winner in 8 bytes, so that testing and replacing it touches one cache line.
  struct Winner {
    Real fitness;
    std::int32_t rank;  // database age rank of the winner, -1 while empty
  };
  std::vector<Winner> winner;
  std::vector<Real> measures;     // cells x N_t
  std::vector<Index> fill_order;  // cells in the order they were first reached
  void reset(Index cells, Index nt) {
    winner.assign(static_cast<std::size_t>(cells), Winner{0, -1});
    measures.resize(static_cast<std::size_t>(cells * nt));
    fill_order.clear();
  }
  Index rank(std::size_t cell) const { return winner[cell].rank; }
  // Offers rows first_rank .. first_rank + n - 1 (cells, fitness, feature-major measures).
  void offer(const std::int32_t* cells, const Real* fit, const Real* measures_t, Index ld, Index nt, Index n,
             Index first_rank) {
    Winner* w = winner.data();
    Real* all_measures = measures.data();
    // The block's cells are known ahead: their winners (80 KB for 10,000 cells, beyond L1)
    // are asked for a few rows early, so the compare below rarely waits on L2.
    constexpr Index kAhead = 16;
    for (Index r = 0; r < n; ++r) {
      if (r + kAhead < n) __builtin_prefetch(w + cells[r + kAhead]);
      const auto cell = static_cast<std::size_t>(cells[r]);
      const Real f = fit[r];
      const Winner old = w[cell];
      if (old.rank < 0) [[unlikely]] fill_order.push_back(static_cast<Index>(cell));
      if (old.rank >= 0 && !(f > old.fitness)) continue;
      w[cell] = Winner{f, static_cast<std::int32_t>(first_rank + r)};
      Real* m = all_measures + cell * static_cast<std::size_t>(nt);
      for (Index t = 0; t < nt; ++t) m[t] = measures_t[t * ld + r];
    }
  }
};

// Offers database ranks [lo, hi) to the maps' cell winners in one pass: for each block of rows
// (read feature-major, as the database keeps them), every map runs its network, bins the
// block's rows and offers them to its cell winners in turn; the block stays in cache meanwhile.
template <BlockBinnedArchive Archive>
void find_winners(const Database& db, std::span<const NeuralFeatureMap* const> maps, std::span<Archive* const> archives,
                  Index lo, Index hi, std::vector<CellWinners>& winners) {
  static_assert(kRebuildBlockRows % kKernelRows == 0, "whole kernel steps per block");
  static_assert(kDatabasePadding >= kKernelRows, "a partial block's last kernel step stays in the database's buffer");
  const Index block = kRebuildBlockRows;
  Index max_outputs = 0;
  for (const NeuralFeatureMap* m : maps) max_outputs = std::max(max_outputs, m->output_size());
  std::vector<Real> targets_t(static_cast<std::size_t>(max_outputs * block));
  std::vector<std::int32_t> cells(static_cast<std::size_t>(block));
  winners.resize(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) winners[i].reset(archives[i]->cells(), maps[i]->output_size());
  // The network reads the database's feature-major copy in place. A partial block's padding
  // columns are the next slots: later rows, older rows or the zero padding, finite either way.
  // Chunks of kRebuildChunkRows rows, map by map: one map's cell winners (~200 KB for 10,000
  // cells) then stay in L2 while it streams the chunk, which the first map brought into L3.
  // Offering block by block to all maps at once made the maps' winners evict each other
  // (perf of a full run: a third of the time on those misses).
  for (const DatabaseSegment& seg : db.segments()) {
    const Index from = std::max<Index>(lo - seg.first_rank, 0), to = std::min<Index>(hi - seg.first_rank, seg.count);
    for (Index chunk = from; chunk < to; chunk += kRebuildChunkRows) {
      const Index chunk_end = std::min(to, chunk + kRebuildChunkRows);
      for (std::size_t i = 0; i < maps.size(); ++i) {
        const NeuralFeatureMap& map = *maps[i];
        // The first map brings the chunk from memory; the others find it in the caches.
        const BaseRows rows = i == 0 ? BaseRows::streamed : BaseRows::cached;
        for (Index first = chunk; first < chunk_end; first += block) {
          const Index n = std::min(block, chunk_end - first);
          map.map_transposed(seg.base_t + first, seg.base_t_ld, n, targets_t.data(), block, rows);
          archives[i]->cells_of_t(targets_t.data(), block, n, cells.data());
          winners[i].offer(cells.data(), seg.fitness + first, targets_t.data(), block, map.output_size(), n,
                           seg.first_rank + first);
        }
      }
    }
  }
}

// The winners of later ranks offered to those of earlier ones, as the later rows themselves
// would be: a cell reached first in `later` is filled in the order `later` reached it, and a
// winner replaces an earlier one only when strictly fitter.
void merge_winners(CellWinners& earlier, const CellWinners& later, Index nt) {
  for (const Index cell : later.fill_order) {
    const auto c = static_cast<std::size_t>(cell);
    const CellWinners::Winner w = later.winner[c];
    CellWinners::Winner& old = earlier.winner[c];
    if (old.rank < 0) earlier.fill_order.push_back(cell);
    else if (!(w.fitness > old.fitness)) continue;
    old = w;
    std::copy_n(later.measures.data() + c * static_cast<std::size_t>(nt), nt,
                earlier.measures.data() + c * static_cast<std::size_t>(nt));
  }
}

// Copies each cell's winner into the (empty) archive, cells in the order they were first reached.
template <BlockBinnedArchive Archive>
void place_winners(const Database& db, const NeuralFeatureMap& map, Archive& archive, const CellWinners& w) {
  const Index nt = map.output_size();
  const bool keep_base = archive.base_feature_size() > 0;
  // The winners lie scattered over the database (tens of MB): prefetching a few cells ahead
  // hides the cache misses that otherwise dominated this copy (perf of a full run: 17%).
  constexpr std::size_t kAhead = 8;
  const std::size_t filled = w.fill_order.size();
  for (std::size_t k = 0; k < filled; ++k) {
    if (k + kAhead < filled) {
      const Index ahead = w.rank(static_cast<std::size_t>(w.fill_order[k + kAhead]));
      prefetch_row(db.genotype(ahead), db.genotype_size());
      if (keep_base) prefetch_row(db.base_features(ahead), db.base_feature_size());
    }
    const auto c = static_cast<std::size_t>(w.fill_order[k]);
    // Each cell once, into an empty archive: the winner's cell is where the bins put it.
    archive.place(static_cast<Index>(c), db.genotype(w.rank(c)), w.winner[c].fitness,
                  w.measures.data() + c * static_cast<std::size_t>(nt), keep_base ? db.base_features(w.rank(c)) : nullptr);
  }
}

// Rebuilds a contiguous group of maps in one pass over the database.
template <BlockBinnedArchive Archive>
void rebuild_group(const Database& db, std::span<const NeuralFeatureMap* const> maps,
                   std::span<Archive* const> archives) {
  std::vector<CellWinners> winners;
  find_winners(db, maps, archives, 0, db.size(), winners);
  for (std::size_t i = 0; i < maps.size(); ++i) place_winners(db, *maps[i], *archives[i], winners[i]);
}

template <BlockBinnedArchive Archive>
void rebuild_all(const Database& db, std::span<const NeuralFeatureMap* const> maps, std::span<Archive* const> archives) {
  check(db, maps, archives);
  for (Archive* a : archives) a->clear();
  if (db.empty() || maps.empty()) return;
  const auto n = static_cast<Index>(maps.size());
  const Index threads = std::max(1, tbb::this_task_arena::max_concurrency());
  if (threads > 1 && n % threads != 0) {
    // Maps that do not split evenly over the threads (one map on two): each thread streams a
    // slice of the database ranks for every map, then each map's slices merge in rank order,
    // which leaves the winners (and the order cells were reached) of one pass over all ranks.
    std::vector<std::vector<CellWinners>> slices(static_cast<std::size_t>(threads));
    tbb::parallel_for(Index{0}, threads, [&](Index t) {
      find_winners(db, maps, archives, t * db.size() / threads, (t + 1) * db.size() / threads,
                   slices[static_cast<std::size_t>(t)]);
    });
    tbb::parallel_for(Index{0}, n, [&](Index m) {
      const auto i = static_cast<std::size_t>(m);
      for (std::size_t t = 1; t < slices.size(); ++t) merge_winners(slices[0][i], slices[t][i], maps[i]->output_size());
      place_winners(db, *maps[i], *archives[i], slices[0][i]);
    });
    return;
  }
  const Index groups = std::min<Index>(n, threads);
  auto group = [&](Index g) {
    const Index lo = g * n / groups;
    const Index hi = (g + 1) * n / groups;
    rebuild_group(db, maps.subspan(static_cast<std::size_t>(lo), static_cast<std::size_t>(hi - lo)),
                  archives.subspan(static_cast<std::size_t>(lo), static_cast<std::size_t>(hi - lo)));
  };
  if (groups == 1) {
    group(0);
  } else {
    tbb::parallel_for(Index{0}, groups, group);
  }
}

}  // namespace

void rebuild_archives(const Database& db, std::span<const NeuralFeatureMap* const> maps,
                      std::span<GridArchive* const> archives) {
  rebuild_all<GridArchive>(db, maps, archives);
}

void rebuild_archive(const Database& db, const NeuralFeatureMap& map, GridArchive& archive) {
  const NeuralFeatureMap* maps[] = {&map};
  GridArchive* archives[] = {&archive};
  check<GridArchive>(db, maps, archives);
  archive.clear();
  rebuild_group<GridArchive>(db, maps, archives);
}

}  // namespace qdmeta
