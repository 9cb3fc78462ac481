#pragma once
// The observers that report on a run and stop it: a progress callback after every generation,
// and a stop flag (set by a signal handler) read between generations.
#include <atomic>
#include <cstdint>
#include <functional>

#include "qdmeta/run/run_observer.hpp"

namespace qdmeta {

// What a progress callback is told after every generation; cheap callbacks only.
struct RunProgress {
  std::int64_t evals = 0;
  std::int64_t budget = 0;
  std::int64_t generation = 0;
  double wall_seconds = 0.0;
  const Algorithm* algorithm = nullptr;
};
using ProgressCallback = std::function<void(const RunProgress&)>;

class ProgressReporter : public RunObserver {
 public:
  explicit ProgressReporter(ProgressCallback callback) : callback_(std::move(callback)) {}
  RunVerdict after_step(const RunStatus& status) override;

 private:
  ProgressCallback callback_;
};

// Stops the run at the next generation boundary once `*flag` is set (before the first step
// when it already is).
class StopOnFlag : public RunObserver {
 public:
  explicit StopOnFlag(const std::atomic<bool>& flag) : flag_(flag) {}
  RunVerdict on_start(const RunStatus&) override { return verdict(); }
  RunVerdict after_step(const RunStatus&) override { return verdict(); }

 private:
  RunVerdict verdict() const { return flag_.load() ? RunVerdict::kStop : RunVerdict::kContinue; }
  const std::atomic<bool>& flag_;
};

}  // namespace qdmeta
