#pragma once
// Drives an algorithm to its evaluation budget. The loop (drive_run) only steps the algorithm and
// tells its observers (run_observer.hpp); run_to_budget adds the standard ones: metrics.csv and
// meta.csv (run_logs.hpp), checkpoints (run_checkpoints.hpp), progress and the stop flag
// (run_progress.hpp), and archive.csv + summary.json at the end (run_outputs.hpp). The run stops
// at the first generation boundary at or past the budget; the overshoot is real and shows in the
// `evals` column.
#include <atomic>
#include <filesystem>
#include <span>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "qdmeta/run/run_observer.hpp"
#include "qdmeta/run/run_progress.hpp"
#include "qdmeta/run/run_result.hpp"
#include "qdmeta/run/run_tables.hpp"
#include "qdmeta/run/summary.hpp"

namespace qdmeta {

// Steps `algorithm` until the budget is reached or an observer answers kStop, telling
// `observers` in order (on_end in reverse order). Writes nothing itself. `resume`: the cursor
// a checkpoint restored (the algorithm already loaded from it). A step that throws
// StepInterrupted (undone by step()) ends the run there as interrupted, every observer told,
// and the exception is then passed on.
RunResult drive_run(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                    std::span<RunObserver* const> observers, const RunCursor* resume = nullptr);

struct RunOptions {
  ProgressCallback progress;                // told after every generation
  const std::atomic<bool>* stop = nullptr;  // once set, the run ends at the next generation boundary
  const RunCursor* resume = nullptr;        // continue from read_checkpoint()'s cursor
  std::vector<RunObserver*> observers;      // the caller's own, told after the standard ones
};

// Runs to the budget, writing metrics.csv (and meta.csv) as it goes and archive.csv +
// summary.json at the end (atomically) into `out_dir`, which must exist. A stop (the flag, an
// observer's kStop, or a step's StepInterrupted, passed on afterwards) ends the run with reason
// kInterrupted; its files are written all the same.
// A checkpointable algorithm also gets checkpoint.bin every `settings.checkpoint_every` seconds
// and when interrupted; the file is removed when the budget is reached.
RunResult run_to_budget(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                        const std::filesystem::path& out_dir, const RunOptions& options);

// The same, with the options most callers need.
inline RunResult run_to_budget(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                               const std::filesystem::path& out_dir, const ProgressCallback& progress = {},
                               const std::atomic<bool>* stop = nullptr, const RunCursor* resume = nullptr) {
  return run_to_budget(algorithm, evaluator, settings, out_dir, RunOptions{progress, stop, resume, {}});
}

}  // namespace qdmeta
