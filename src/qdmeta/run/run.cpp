#include "qdmeta/run/run.hpp"

#include <fmt/format.h>

#include <exception>
#include <optional>
#include <ranges>

#include "qdmeta/run/run_checkpoints.hpp"
#include "qdmeta/run/run_logs.hpp"
#include "qdmeta/run/run_outputs.hpp"

namespace qdmeta {

RunResult drive_run(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                    std::span<RunObserver* const> observers, const RunCursor* resume) {
  const RunClock clock(resume ? resume->wall_seconds : 0.0);
  RunCursor cursor = resume ? *resume : RunCursor{};
  RunStatus status{algorithm, settings, settings.evals(algorithm.counters()), clock, cursor};

  bool stop = false;  // every observer is told, whatever the others answer
  for (RunObserver* o : observers) stop = o->on_start(status) == RunVerdict::kStop || stop;
  RunResult result;
  std::exception_ptr interrupted;  // a StepInterrupted, passed on once the run has ended
  while (status.evals < settings.budget) {
    if (stop) {
      result.reason = StopReason::kInterrupted;
      break;
    }
    for (RunObserver* o : observers) o->before_step(status);
    try {
      algorithm.step(evaluator);
    } catch (const EvaluationAborted& e) {
      for (RunObserver* o : observers) o->on_step_aborted(status, e);
      throw;
    } catch (const StepInterrupted&) {
      if (algorithm.step_in_progress()) throw;  // not undone: no boundary to end at
      interrupted = std::current_exception();
      result.reason = StopReason::kInterrupted;
      break;
    }
    status.evals = settings.evals(algorithm.counters());
    for (RunObserver* o : observers) stop = o->after_step(status) == RunVerdict::kStop || stop;
  }

  result.counters = algorithm.counters();
  result.evals = status.evals;
  result.generations = algorithm.generation();
  result.stats = algorithm.stats();
  result.wall_seconds = clock.seconds();
  result.message = result.reason == StopReason::kBudget
                       ? fmt::format("reached the budget of {} evaluations ({} spent)", settings.budget, status.evals)
                       : fmt::format("interrupted after {} of {} evaluations", status.evals, settings.budget);
  for (RunObserver* o : std::views::reverse(observers)) o->on_end(status, result);
  if (interrupted) std::rethrow_exception(interrupted);
  return result;
}

RunResult run_to_budget(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                        const std::filesystem::path& out_dir, const RunOptions& options) {
  // The metrics file first: a resume whose metrics.csv does not match is refused before meta.csv is cut.
  MetricsLogger metrics(out_dir / "metrics.csv", options.resume);
  MetaLogger meta(out_dir / "meta.csv", options.resume);
  RunOutputs outputs(out_dir, evaluator.workers());
  // Told in this order after each step; at the end in reverse: the checkpoint of an interrupted
  // run before the closing metrics row, the summary last of all.
  std::vector<RunObserver*> observers = {&outputs, &meta, &metrics};
  std::optional<CheckpointWriter> checkpoints;
  std::optional<AbortCheckpoint> abort_checkpoint;
  if (algorithm.checkpointable()) {
    observers.push_back(&checkpoints.emplace(out_dir, settings.fingerprint));
    if (evaluator.may_abort()) observers.push_back(&abort_checkpoint.emplace(out_dir, settings.fingerprint));
  }
  std::optional<ProgressReporter> progress;
  if (options.progress) observers.push_back(&progress.emplace(options.progress));
  observers.insert(observers.end(), options.observers.begin(), options.observers.end());
  std::optional<StopOnFlag> stop;
  if (options.stop) observers.push_back(&stop.emplace(*options.stop));
  return drive_run(algorithm, evaluator, settings, observers, options.resume);
}

}  // namespace qdmeta
