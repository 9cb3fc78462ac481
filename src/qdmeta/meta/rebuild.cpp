#include "qdmeta/meta/rebuild.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

void check(const Database& db, std::span<const NeuralFeatureMap* const> maps, std::span<GridArchive* const> archives) {
  if (maps.size() != archives.size())
    throw InputError(fmt::format("rebuild: {} feature-maps but {} archives", maps.size(), archives.size()));
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (maps[i] == nullptr) throw InputError(fmt::format("rebuild: feature-map {} is null", i));
    if (archives[i] == nullptr) throw InputError(fmt::format("rebuild: archive {} is null", i));
    const NeuralFeatureMap& map = *maps[i];
    const GridArchive& archive = *archives[i];
    if (map.input_size() != db.base_feature_size())
      throw InputError(fmt::format("rebuild: feature-map {} reads {} base features but the database stores {}", i,
                                   map.input_size(), db.base_feature_size()));
    if (map.output_size() != archive.dimensions())
      throw InputError(fmt::format("rebuild: feature-map {} gives {} target features but archive {} has {} dimensions",
                                   i, map.output_size(), i, archive.dimensions()));
    if (archive.params().solution_size != db.genotype_size())
      throw InputError(fmt::format("rebuild: archive {} stores solutions of {} genes but the database stores {}", i,
                                   archive.params().solution_size, db.genotype_size()));
    const Index keep = archive.params().base_feature_size;
    if (keep != 0 && keep != db.base_feature_size())
      throw InputError(fmt::format("rebuild: archive {} keeps {} base features but the database stores {}", i, keep,
                                   db.base_feature_size()));
    for (std::size_t j = 0; j < i; ++j)
      if (archives[j] == archives[i]) throw InputError(fmt::format("rebuild: archives {} and {} are the same", j, i));
  }
}

// Rebuilds a contiguous group of maps in one pass over the database: each block of rows is
// transposed once, then mapped and inserted into every archive of the group in turn.
void rebuild_group(const Database& db, std::span<const NeuralFeatureMap* const> maps,
                   std::span<GridArchive* const> archives) {
  const Index nb = db.base_feature_size();
  const Index block = kRebuildBlockRows;
  Index scratch_size = 0;
  Index max_outputs = 0;
  for (const NeuralFeatureMap* m : maps) {
    scratch_size = std::max(scratch_size, m->scratch_size(block));
    max_outputs = std::max(max_outputs, m->output_size());
  }
  std::vector<Real> base_t(static_cast<std::size_t>(nb * block));
  std::vector<Real> scratch(static_cast<std::size_t>(scratch_size));
  std::vector<Real> targets(static_cast<std::size_t>(max_outputs * block));
  for (const DatabaseSegment& seg : db.segments()) {
    for (Index first = 0; first < seg.count; first += block) {
      const Index n = std::min(block, seg.count - first);
      const Real* rows = seg.base_row(first);
      transpose_rows(rows, n, nb, base_t.data());
      for (std::size_t i = 0; i < maps.size(); ++i) {
        const NeuralFeatureMap& map = *maps[i];
        GridArchive& archive = *archives[i];
        map.map_transposed(base_t.data(), n, scratch.data(), targets.data());
        const Index nt = map.output_size();
        const bool keep_base = archive.params().base_feature_size > 0;
        for (Index r = 0; r < n; ++r)
          archive.add(seg.genotype(first + r), seg.fitness[first + r], targets.data() + r * nt,
                      keep_base ? seg.base_row(first + r) : nullptr);
      }
    }
  }
}

}  // namespace

void rebuild_archives(const Database& db, std::span<const NeuralFeatureMap* const> maps,
                      std::span<GridArchive* const> archives) {
  check(db, maps, archives);
  for (GridArchive* a : archives) a->clear();
  if (db.empty() || maps.empty()) return;
  const auto n = static_cast<Index>(maps.size());
  const Index groups = std::min<Index>(n, std::max(1, tbb::this_task_arena::max_concurrency()));
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

void rebuild_archive(const Database& db, const NeuralFeatureMap& map, GridArchive& archive) {
  const NeuralFeatureMap* maps[] = {&map};
  GridArchive* archives[] = {&archive};
  check(db, maps, archives);
  archive.clear();
  rebuild_group(db, maps, archives);
}

}  // namespace qdmeta
