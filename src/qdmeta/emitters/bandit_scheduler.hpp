#pragma once
// pyribs's BanditScheduler: a Scheduler (scheduler.hpp) over a pool of emitters that asks only
// num_active of them at a time, chosen by UCB1 on how many of each one's rows the archive took
// (emitter_bandit.hpp). Thresholds, add mode, archive and checkpoints are the Scheduler's.
//
//   BanditScheduler scheduler(archive, ThresholdParams{0.01, 0.0}, std::move(pool),
//                             BanditParams{.num_active = 4});
//   const RowMatrix& x = scheduler.ask(rng);   // the active emitters' rows, in pool order
//   scheduler.tell(objectives, measures);
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "qdmeta/emitters/emitter_bandit.hpp"
#include "qdmeta/emitters/scheduler.hpp"

namespace qdmeta {

template <CellIndexedArchive A>
class BanditScheduler {
 public:
  BanditScheduler(A& archive, ThresholdParams thresholds, std::vector<std::unique_ptr<Emitter>> pool,
                  BanditParams params, AddMode add_mode = AddMode::kSingle)
      : scheduler_(archive, thresholds, std::move(pool), add_mode), bandit_(scheduler_.emitter_count(), params) {}

  const Scheduler<A>& scheduler() const { return scheduler_; }
  const EmitterBandit& bandit() const { return bandit_; }
  A& archive() { return scheduler_.archive(); }
  const CellThresholds& thresholds() const { return scheduler_.thresholds(); }
  Index batch_size() const { return scheduler_.batch_size(); }
  const RowMatrix& solutions() const { return scheduler_.solutions(); }
  std::span<const ThresholdOutcome> outcomes() const { return scheduler_.outcomes(); }

  // Chooses the active emitters, then asks each of them (the Scheduler's ask).
  const RowMatrix& ask(Rng& rng) {
    if (scheduler_.awaiting_tell())
      throw InputError("BanditScheduler::ask: called twice without tell; tell the last batch's results first");
    std::vector<std::int64_t> runs(scheduler_.emitter_count());
    for (std::size_t i = 0; i < runs.size(); ++i) runs[i] = scheduler_.emitter(i).ended_runs();
    scheduler_.set_active(bandit_.choose(runs));
    return scheduler_.ask(rng);
  }

  // The Scheduler's tell; then each active emitter's rows and successes (rows the thresholds
  // took) go to UCB1.
  void tell(std::span<const Real> objectives, RowsView measures, std::span<const std::uint8_t> valid = {}) {
    scheduler_.tell(objectives, measures, valid);
    const std::span<const ThresholdOutcome> outcomes = scheduler_.outcomes();
    std::size_t row = 0;
    for (std::size_t i = 0; i < scheduler_.emitter_count(); ++i) {
      if (!scheduler_.active()[i]) continue;
      const auto rows = static_cast<std::size_t>(scheduler_.emitter(i).batch_size());
      Index taken = 0;
      for (const ThresholdOutcome& o : outcomes.subspan(row, rows)) taken += o.status != AddStatus::kNotAdded;
      bandit_.record(i, static_cast<Index>(rows), taken);
      row += rows;
    }
  }

  // The bandit, then the Scheduler (the caller saves the archive).
  void save(BinaryWriter& out) const {
    out.tag("bandit scheduler");
    bandit_.save(out);
    scheduler_.save(out);
  }
  void load(BinaryReader& in) {
    in.expect_tag("bandit scheduler");
    bandit_.load(in);
    const auto& active = bandit_.active();
    // Before the first ask nothing is active, and the Scheduler's rows are all its emitters'.
    scheduler_.set_active(std::find(active.begin(), active.end(), 1) != active.end()
                              ? active
                              : std::vector<std::uint8_t>(active.size(), 1));
    scheduler_.load(in);
  }

 private:
  Scheduler<A> scheduler_;
  EmitterBandit bandit_;
};

}  // namespace qdmeta
