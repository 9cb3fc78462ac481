#pragma once
// [archive] kind = "floor": a grid that admits only solutions whose objective reaches `floor`, an
// archive of good-enough solutions only (for the arm: joint angles whose variance is at most
// -floor). docs/tutorials/archive.md builds it.
#include <qdmeta/archive/grid_archive.hpp>
#include <qdmeta/plugin/part_registries.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace qdmeta {
class ConfigReader;
}

namespace arm {

// Every member but add_batch is the grid's own: the floor only filters what comes in.
class FloorArchive {
 public:
  FloorArchive(qdmeta::GridArchiveParams grid, double floor);
  qdmeta::Index cells() const { return grid_.cells(); }
  qdmeta::Index dimensions() const { return grid_.dimensions(); }
  qdmeta::Index size() const { return grid_.size(); }
  bool empty() const { return grid_.empty(); }
  qdmeta::Index solution_size() const { return grid_.solution_size(); }
  qdmeta::Index base_feature_size() const { return grid_.base_feature_size(); }
  qdmeta::Index sample_cell(qdmeta::Rng& rng) const { return grid_.sample_cell(rng); }
  const qdmeta::Real* solution(qdmeta::Index cell) const { return grid_.solution(cell); }
  qdmeta::Real objective(qdmeta::Index cell) const { return grid_.objective(cell); }
  const std::vector<qdmeta::Index>& filled_cells() const { return grid_.filled_cells(); }
  qdmeta::ArchiveStats stats() const { return grid_.stats(); }
  qdmeta::EliteTable elites() const { return grid_.elites(); }
  void clear() { grid_.clear(); }
  // Rows below the floor are treated as invalid (not added); the rest go to the grid.
  qdmeta::Index add_batch(const qdmeta::EliteBatch& batch, std::span<qdmeta::AddStatus> status = {});
  void save(qdmeta::BinaryWriter& out) const;
  void load(qdmeta::BinaryReader& in);

 private:
  qdmeta::GridArchive grid_;
  double floor_;
  std::vector<std::uint8_t> valid_;  // add_batch's scratch: the batch's valid flags, floored
};

// [archive] kind = "floor": keys `bins` (default [32, 32]) and `floor` (default 0: no floor for a
// task whose objectives are at most 0, as the arm's).
qdmeta::AnyArchive read_floor_archive(qdmeta::ConfigReader& archive, const qdmeta::ArchiveShape& shape,
                                      qdmeta::MemoryEstimate& memory);

// Makes `[archive] kind = "floor"` available to configs (qdmeta's archive registry).
void register_floor_archive();

}  // namespace arm
