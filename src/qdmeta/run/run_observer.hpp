#pragma once
// What watches a run: the driver loop (drive_run, run.hpp) only steps the algorithm and tells its
// observers; logging, checkpoints, progress and stopping are each one observer.
//
// A library user adds their own by deriving from RunObserver, overriding the hooks it needs, and
// passing it in RunOptions::observers:
//
//   struct StopWhenCovered : RunObserver {  // ends the run early once 90% of the cells are filled
//     RunVerdict after_step(const RunStatus& s) override {
//       return s.algorithm.stats().coverage >= 0.9 ? RunVerdict::kStop : RunVerdict::kContinue;
//     }
//   };
//   StopWhenCovered covered;
//   RunOptions options;
//   options.observers = {&covered};
//   run_to_budget(algorithm, evaluator, settings, out_dir, options);
//
// Hooks run on the driver's thread between steps, so an observer may read the algorithm but
// must be cheap: after_step runs after every generation.
#include <chrono>
#include <cstdint>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "qdmeta/run/run_result.hpp"

namespace qdmeta {

// An observer's answer after a step: kStop ends the run at this generation boundary with
// StopReason::kInterrupted (a checkpointable run can then be resumed), unless the step reached
// the budget, which wins.
enum class RunVerdict { kContinue, kStop };

// The run's time, counting the time before a resume.
class RunClock {
 public:
  explicit RunClock(double seconds_before) : before_(seconds_before) {}
  double seconds() const { return before_ + std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_ = Clock::now();
  double before_;
};

// What every hook sees.
struct RunStatus {
  const Algorithm& algorithm;
  const RunSettings& settings;
  std::int64_t evals = 0;  // what the budget counts, after the last finished step
  const RunClock& clock;
  // The built-in observers' place in their files, saved in checkpoints: they update it, a
  // custom observer should only read it.
  RunCursor& cursor;
};

class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // Before the first step (of this session, for a resumed run); kStop ends the run unstepped.
  virtual RunVerdict on_start(const RunStatus&) { return RunVerdict::kContinue; }
  virtual void before_step(const RunStatus&) {}
  // After every finished step. Every observer is told, whatever the others answer.
  virtual RunVerdict after_step(const RunStatus&) { return RunVerdict::kContinue; }
  // The step threw EvaluationAborted (a distributed worker was lost); the driver rethrows it
  // afterwards, unless an observer throws a replacement.
  virtual void on_step_aborted(const RunStatus&, const EvaluationAborted&) {}
  // The run has ended. Called in reverse order, as destructors run: an observer that builds on
  // an earlier one (the checkpoint writer on the loggers' byte counts) ends before it.
  virtual void on_end(const RunStatus&, const RunResult&) {}
};

}  // namespace qdmeta
