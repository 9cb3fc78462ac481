#include "floor_archive.hpp"

#include <qdmeta/plugin/config.hpp>

#include <utility>

namespace arm {

FloorArchive::FloorArchive(qdmeta::GridArchiveParams grid, double floor) : grid_(std::move(grid)), floor_(floor) {}

qdmeta::Index FloorArchive::add_batch(const qdmeta::EliteBatch& batch, std::span<qdmeta::AddStatus> status) {
  valid_.resize(static_cast<std::size_t>(batch.rows()));
  for (qdmeta::Index r = 0; r < batch.rows(); ++r)
    valid_[static_cast<std::size_t>(r)] = batch.is_valid(r) && batch.objectives[static_cast<std::size_t>(r)] >= floor_;
  qdmeta::EliteBatch floored = batch;
  floored.valid = valid_;
  return grid_.add_batch(floored, status);
}

// A checkpoint holds the grid; the floor comes from the config, which the checkpoint's
// fingerprint pins.
void FloorArchive::save(qdmeta::BinaryWriter& out) const {
  out.tag("floor_archive");
  grid_.save(out);
}

void FloorArchive::load(qdmeta::BinaryReader& in) {
  in.expect_tag("floor_archive");
  grid_.load(in);
}

qdmeta::AnyArchive read_floor_archive(qdmeta::ConfigReader& archive, const qdmeta::ArchiveShape& shape,
                                      qdmeta::MemoryEstimate& memory) {
  qdmeta::GridArchiveParams grid;
  const auto bins = archive.integers("bins", {32, 32}, 1, 100'000, 1, 16);
  grid.bins.assign(bins.begin(), bins.end());
  grid.solution_size = shape.solution_size;
  grid.qd_offset = shape.qd_offset;
  const double floor = archive.number("floor", 0.0, -1e30, 1e30);
  memory.add("the floor archive", "archive.bins (cells) x genes", qdmeta::grid_archive_bytes(grid));
  return qdmeta::AnyArchive(FloorArchive(std::move(grid), floor));
}

void register_floor_archive() { qdmeta::archive_registry().add("floor", read_floor_archive); }

}  // namespace arm
