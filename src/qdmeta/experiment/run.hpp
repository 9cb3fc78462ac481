#pragma once
// Drives an algorithm to its evaluation budget: metrics rows, progress, final archive and a
// summary. The run stops at the first generation boundary at or past the budget; the
// overshoot is real and shows in the `evals` column.
#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/experiment/build.hpp"
#include "qdmeta/experiment/checkpoint.hpp"

namespace qdmeta {

enum class StopReason { kBudget, kInterrupted };
inline constexpr EnumNames<StopReason, 2> kStopReasonNames{{{StopReason::kBudget, "budget"},
                                                            {StopReason::kInterrupted, "interrupted"}}};

struct RunResult {
  StopReason reason = StopReason::kBudget;
  std::string message;
  EvaluationCounters counters;
  std::int64_t evals = 0;  // what the budget counts
  std::int64_t generations = 0;
  ArchiveStats stats;
  double wall_seconds = 0.0;
};

// Called after every generation; cheap callbacks only.
struct RunProgress {
  std::int64_t evals = 0;
  std::int64_t budget = 0;
  std::int64_t generation = 0;
  double wall_seconds = 0.0;
  const Algorithm* algorithm = nullptr;
};
using ProgressCallback = std::function<void(const RunProgress&)>;

// The metrics.csv header (README.md's run-directory table).
const std::vector<std::string>& metrics_columns();
// The meta.csv header (QD-Meta): one row per meta-generation.
const std::vector<std::string>& meta_columns();

// Why the run in `dir` stopped, from its summary.json; nullopt when there is none (a run still
// going, or killed). Throws InputError on an unreadable summary.
std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir);

// Runs to the budget, writing metrics.csv as it goes and archive.csv + summary.json at the
// end (atomically) into `out_dir`, which must exist. Setting `*stop` ends the run at the next
// generation boundary with reason kInterrupted; its files are written all the same.
// A checkpointable algorithm also gets checkpoint.bin every `settings.checkpoint_every` seconds
// and when interrupted; the file is removed when the budget is reached. `resume` continues a
// run from its checkpoint: `algorithm` already loaded, the cursor from read_checkpoint().
RunResult run_to_budget(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                        const std::filesystem::path& out_dir, const ProgressCallback& progress = {},
                        const std::atomic<bool>* stop = nullptr, const RunCursor* resume = nullptr);

}  // namespace qdmeta
