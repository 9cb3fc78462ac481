// Tests that archive.clear() resets a Scheduler's CMA-MAE thresholds (scheduler.hpp), as pyribs's
// cleared archive scores every cell against threshold_min again, and that loading a checkpoint
// into the archive is not taken for a clear.
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <vector>

#include "qdmeta/emitters/gaussian_emitter.hpp"
#include "qdmeta/emitters/scheduler.hpp"
#include "sphere_problem.hpp"

namespace qdmeta {
namespace {

using test::kSphereGenes;
using test::sphere_grid;

// A scheduler of one Gaussian emitter of one row, whose rows' objective and measures the test sets.
Scheduler<GridArchive> one_row_scheduler(GridArchive& archive, double alpha, double threshold_min) {
  GaussianEmitterParams p;
  p.x0.assign(kSphereGenes, 0.0);
  p.batch_size = 1;
  std::vector<std::unique_ptr<Emitter>> emitters;
  emitters.push_back(std::make_unique<GaussianEmitter>(p, elite_picker(archive)));
  return Scheduler<GridArchive>(archive, ThresholdParams{alpha, threshold_min}, std::move(emitters));
}

// Asks, then tells the one row `objective` at measures (1, 1).
ThresholdOutcome tell_one(Scheduler<GridArchive>& s, Rng& rng, Real objective) {
  s.ask(rng);
  const std::vector<Real> objectives{objective};
  const std::vector<Real> measures{1.0F, 1.0F};
  s.tell(objectives, RowsView(measures.data(), 1, 2));
  return s.outcomes()[0];
}

TEST(SchedulerClear, ClearResetsCmaMaeThresholdsToThresholdMin) {
  GridArchive archive(sphere_grid());
  auto s = one_row_scheduler(archive, 0.5, 0.0);
  Rng rng(1);
  EXPECT_EQ(tell_one(s, rng, 4.0F).status, AddStatus::kNew);
  const Index cell = archive.filled_cells().front();
  EXPECT_EQ(s.thresholds().threshold(cell), 2.0);  // 0.5 * 0 + 0.5 * 4
  archive.clear();
  EXPECT_EQ(s.thresholds().threshold(cell), 0.0);
  EXPECT_FALSE(s.thresholds().reached(cell));
  // 1 is below the old threshold 2; against threshold_min it is a new cell of improvement 1.
  const ThresholdOutcome after = tell_one(s, rng, 1.0F);
  EXPECT_EQ(after.status, AddStatus::kNew);
  EXPECT_EQ(after.improvement, 1.0);
  EXPECT_EQ(s.thresholds().threshold(cell), 0.5);
}

TEST(SchedulerClear, ClearResetsCmaMeThresholdsToMinusInfinity) {
  GridArchive archive(sphere_grid());
  auto s = one_row_scheduler(archive, 1.0, -std::numeric_limits<double>::infinity());
  Rng rng(2);
  tell_one(s, rng, 4.0F);
  archive.clear();
  const ThresholdOutcome after = tell_one(s, rng, 1.0F);
  EXPECT_EQ(after.status, AddStatus::kNew);  // it would not beat the 4 the cell had before
  EXPECT_EQ(after.improvement, 1.0);
  EXPECT_EQ(archive.size(), 1);
}

TEST(SchedulerClear, LoadingTheArchiveIsNotAClearAndCheckpointsKeepTheReset) {
  GridArchive archive(sphere_grid());
  auto s = one_row_scheduler(archive, 0.5, 0.0);
  Rng rng(3);
  tell_one(s, rng, 4.0F);
  BinaryWriter archive_only;
  archive.save(archive_only);
  BinaryReader in(archive_only.bytes(), "test");
  archive.load(in);
  EXPECT_EQ(s.thresholds().threshold(archive.filled_cells().front()), 2.0);

  archive.clear();
  BinaryWriter out;
  archive.save(out);
  s.save(out);  // saves the thresholds as the clear left them
  GridArchive restored(sphere_grid());
  auto t = one_row_scheduler(restored, 0.5, 0.0);
  BinaryReader both(out.bytes(), "test");
  restored.load(both);
  t.load(both);
  both.finish();
  EXPECT_EQ(t.thresholds(), s.thresholds());
  EXPECT_EQ(t.thresholds(), CellThresholds(archive.cells(), ThresholdParams{0.5, 0.0}));
}

}  // namespace
}  // namespace qdmeta
