#pragma once
// CMA-ME and CMA-MAE as one ask/tell loop (Fontaine et al. 2020; Fontaine & Nikolaidis 2023):
// ask() stacks each emitter's batch in emitter order; tell() takes the rows' objectives and
// measures, adds every row to the archive under the thresholds (thresholded_add.hpp), and tells
// each emitter the outcomes of its own rows: at once on oneTBB when every emitter tells_alone()
// (each then touches only itself, so the bits do not depend on the threads), in order otherwise.
// ask() likewise asks at once emitters that draw from streams of their own (asks_alone()).
// ThresholdParams{alpha = 1, threshold_min = -inf} is CMA-ME; alpha < 1 with a finite
// threshold_min is CMA-MAE. The archive is the caller's result archive (each cell keeps its
// best elite); the scheduler holds the thresholds beside it, and archive.clear() resets them to
// threshold_min (as pyribs, whose empty cells score against threshold_min whatever their
// threshold was). `add_mode` is pyribs's: kSingle (the default) offers
// the rows to the thresholds one at a time, in order; kBatch scores them all against the
// thresholds before the batch (CellThresholds::offer_batch).
//
//   GridArchive archive(grid_params);
//   Scheduler scheduler(archive, ThresholdParams{0.01, 0.0},
//                       make_evolution_strategy_emitters(archive, emitter_params, 5));
//   const RowMatrix& x = scheduler.ask(rng);   // evaluate each row...
//   scheduler.tell(objectives, measures);
#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/parallel.hpp"
#include "qdmeta/emitters/emitter.hpp"
#include "qdmeta/emitters/evolution_strategy_emitter.hpp"
#include "qdmeta/emitters/thresholded_add.hpp"

namespace qdmeta {

// The emitters' draw of an elite (a restart's mean, a Gaussian emitter's parent): a uniformly drawn elite of `archive` (which must outlive them).
template <CellIndexedArchive A>
ElitePicker elite_picker(const A& archive) {
  return [&archive](Rng& rng, std::vector<double>& mean) {
    if (archive.empty()) return false;
    const Real* elite = archive.solution(archive.sample_cell(rng));
    for (std::size_t j = 0; j < mean.size(); ++j) mean[j] = elite[j];
    return true;
  };
}

// `count` emitters of the same params that restart from elites of `archive`.
template <CellIndexedArchive A>
std::vector<std::unique_ptr<Emitter>> make_evolution_strategy_emitters(const A& archive,
                                                                       const EvolutionStrategyEmitterParams& params,
                                                                       int count) {
  std::vector<std::unique_ptr<Emitter>> emitters;
  for (int i = 0; i < count; ++i) emitters.push_back(std::make_unique<EvolutionStrategyEmitter>(params, elite_picker(archive)));
  return emitters;
}

template <CellIndexedArchive A>
class Scheduler {
 public:
  Scheduler(A& archive, ThresholdParams thresholds, std::vector<std::unique_ptr<Emitter>> emitters,
            AddMode add_mode = AddMode::kSingle)
      : archive_(archive),
        add_mode_(add_mode),
        thresholds_(archive.cells(), thresholds),
        seen_clears_(archive.clears()),
        emitters_(std::move(emitters)),
        active_(emitters_.size(), 1) {
    if (emitters_.empty()) throw InputError("Scheduler emitters is empty: give at least one emitter");
    if (add_mode != AddMode::kSingle && add_mode != AddMode::kBatch)
      throw InputError(fmt::format("Scheduler add_mode = {} is invalid: must be single or batch", static_cast<int>(add_mode)));
    Index rows = 0;
    for (std::size_t i = 0; i < emitters_.size(); ++i) {
      if (!emitters_[i]) throw InputError(fmt::format("Scheduler emitters[{}] is null", i));
      if (emitters_[i]->solution_size() != archive.solution_size()) {
        throw InputError(fmt::format("Scheduler emitters[{}] proposes {} genes; the archive holds {}", i,
                                     emitters_[i]->solution_size(), archive.solution_size()));
      }
      rows += emitters_[i]->batch_size();
    }
    solutions_.setZero(rows, archive.solution_size());  // zero: a checkpoint before the first ask() is deterministic
    outcomes_.resize(static_cast<std::size_t>(rows));
  }

  // The rows of the next (or pending) ask: the active emitters' batches.
  Index batch_size() const { return solutions_.rows(); }
  std::size_t emitter_count() const { return emitters_.size(); }
  // Which emitters ask() asks and tell() tells, one flag per emitter: all unless set_active()
  // (a BanditScheduler's choice) says otherwise.
  const std::vector<std::uint8_t>& active() const { return active_; }
  // Only between a tell and the next ask; at least one emitter; InputError otherwise.
  void set_active(std::vector<std::uint8_t> active) {
    if (awaiting_tell_) throw InputError("Scheduler::set_active: called between ask and tell");
    if (active.size() != emitters_.size() || std::find(active.begin(), active.end(), 1) == active.end())
      throw InputError(fmt::format("Scheduler::set_active: give {} flags, at least one set", emitters_.size()));
    active_ = std::move(active);
    solutions_.setZero(active_rows(), solutions_.cols());
  }
  bool awaiting_tell() const { return awaiting_tell_; }
  AddMode add_mode() const { return add_mode_; }
  const Emitter& emitter(std::size_t i) const { return *emitters_[i]; }
  A& archive() { return archive_; }
  // threshold_min in every cell since the archive's last clear().
  const CellThresholds& thresholds() const {
    follow_clears();
    return thresholds_;
  }
  // The last ask()'s rows (all zero before the first ask()).
  const RowMatrix& solutions() const { return solutions_; }
  // The last tell's outcomes, one per row.
  std::span<const ThresholdOutcome> outcomes() const { return outcomes_; }

  // A warm start over an archive that already holds elites (QD-Meta's rebuilt maps): each filled
  // cell's threshold starts at its elite's objective (CellThresholds::raise_to), the others at
  // threshold_min.
  void start_thresholds_at_elites() {
    thresholds_.clear();
    for (Index cell : archive_.filled_cells()) thresholds_.raise_to(cell, archive_.objective(cell));
  }

  // Every emitter's batch, stacked in emitter order; valid until the next ask() or load().
  const RowMatrix& ask(Rng& rng) {
    if (awaiting_tell_) throw InputError("Scheduler::ask: called twice without tell; tell the last batch's results first");
    const std::vector<std::pair<Emitter*, Index>> asked = active_emitters();
    const auto ask_one = [&](std::size_t k) {
      const RowMatrix& batch = asked[k].first->ask(rng);
      solutions_.middleRows(asked[k].second, batch.rows()) = batch;
    };
    if (at_once(asked, &Emitter::asks_alone)) {
      parallel_indices_lowest_error(static_cast<Index>(asked.size()), [&](Index k) { ask_one(static_cast<std::size_t>(k)); });
    } else {
      for (std::size_t k = 0; k < asked.size(); ++k) ask_one(k);
    }
    awaiting_tell_ = true;
    return solutions_;
  }

  // The objectives and measures of the last ask()'s rows, in its order; `valid` (one flag per
  // row, empty: all valid) marks rows that enter no cell (a task's invalid solutions);
  // `base_features` go along into an archive that keeps them.
  void tell(std::span<const Real> objectives, RowsView measures, std::span<const std::uint8_t> valid = {},
            RowsView base_features = {}) {
    if (!awaiting_tell_) throw InputError("Scheduler::tell: called without a pending ask; call ask() first");
    follow_clears();
    outcomes_.resize(static_cast<std::size_t>(solutions_.rows()));
    add_with_thresholds(archive_, thresholds_, EliteBatch{solutions_, objectives, measures, base_features, valid},
                        outcomes_, add_mode_);
    awaiting_tell_ = false;
    const std::vector<std::pair<Emitter*, Index>> told = active_emitters();
    const auto tell_one = [&](std::size_t k) {
      const auto [emitter, first_row] = told[k];
      const Index rows = emitter->batch_size();
      const auto first = static_cast<std::size_t>(first_row);
      const auto count = static_cast<std::size_t>(rows);
      emitter->tell({RowsView(solutions_.row(first_row).data(), rows, solutions_.cols()), objectives.subspan(first, count),
                     RowsView(measures.row(first_row), rows, measures.cols, measures.stride),
                     std::span<const ThresholdOutcome>(outcomes_).subspan(first, count)});
    };
    if (at_once(told, &Emitter::tells_alone)) {
      parallel_indices_lowest_error(static_cast<Index>(told.size()), [&](Index k) { tell_one(static_cast<std::size_t>(k)); });
    } else {
      for (std::size_t k = 0; k < told.size(); ++k) tell_one(k);
    }
  }

  // Checkpoints of the thresholds and emitters (the caller saves the archive); load() into a
  // scheduler built alike (the add mode is a setting, as the emitters' params are, and not saved).
  void save(BinaryWriter& out) const {
    out.tag("emitter scheduler");
    thresholds().save(out);
    for (const auto& emitter : emitters_) emitter->save(out);
    out.boolean(awaiting_tell_);
    out.matrix(solutions_);
  }
  void load(BinaryReader& in) {
    in.expect_tag("emitter scheduler");
    thresholds_.load(in);
    seen_clears_ = archive_.clears();  // the checkpoint's thresholds are those after its clears
    for (auto& emitter : emitters_) emitter->load(in);
    awaiting_tell_ = in.boolean("scheduler pending flag");
    RowMatrix solutions;
    in.matrix(solutions, "scheduler batch");
    if (solutions.rows() != active_rows() || solutions.cols() != solutions_.cols()) {
      in.fail(fmt::format("the scheduler batch is {}x{}, expected {}x{}", solutions.rows(), solutions.cols(),
                          active_rows(), solutions_.cols()));
    }
    solutions_ = std::move(solutions);
  }

 private:
  // Each active emitter and the first row of its batch, in emitter order.
  std::vector<std::pair<Emitter*, Index>> active_emitters() const {
    std::vector<std::pair<Emitter*, Index>> active;
    Index row = 0;
    for (std::size_t i = 0; i < emitters_.size(); ++i) {
      if (!active_[i]) continue;
      active.emplace_back(emitters_[i].get(), row);
      row += emitters_[i]->batch_size();
    }
    return active;
  }
  // True when there are several emitters and each says `alone` (tells_alone or asks_alone).
  static bool at_once(const std::vector<std::pair<Emitter*, Index>>& emitters, bool (Emitter::*alone)() const) {
    return emitters.size() > 1 &&
           std::all_of(emitters.begin(), emitters.end(), [alone](const auto& e) { return (e.first->*alone)(); });
  }

  Index active_rows() const {
    Index rows = 0;
    for (std::size_t i = 0; i < emitters_.size(); ++i) rows += active_[i] ? emitters_[i]->batch_size() : 0;
    return rows;
  }

  // Resets the thresholds once per archive clear() since they last looked; mutable, as reading
  // them must not show thresholds the cleared archive no longer has.
  void follow_clears() const {
    if (archive_.clears() == seen_clears_) return;
    thresholds_.clear();
    seen_clears_ = archive_.clears();
  }

  A& archive_;
  AddMode add_mode_;
  mutable CellThresholds thresholds_;
  mutable std::uint64_t seen_clears_;
  std::vector<std::unique_ptr<Emitter>> emitters_;
  std::vector<std::uint8_t> active_;
  RowMatrix solutions_;
  std::vector<ThresholdOutcome> outcomes_;
  bool awaiting_tell_ = false;
};

}  // namespace qdmeta
