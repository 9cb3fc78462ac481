#pragma once
// The observers that keep a checkpointable run resumable: checkpoint.bin on a timer and when the
// run is interrupted, and (for an evaluator that can lose a worker midway through a step) the
// state before each step, written should the step fail.
#include <cstdint>
#include <filesystem>
#include <optional>

#include "qdmeta/run/run_observer.hpp"

namespace qdmeta {

// Writes checkpoint.bin after the first step (so that a run killed early can be resumed too),
// then every `[checkpoint] every_seconds`, and at the end of an interrupted run, before the
// metrics logger's closing row (it ends first), so that a resumed run's logs continue exactly
// as an uninterrupted run's would. Never once the budget is reached.
class CheckpointWriter : public RunObserver {
 public:
  CheckpointWriter(std::filesystem::path dir, std::uint64_t fingerprint);
  RunVerdict on_start(const RunStatus& status) override;
  RunVerdict after_step(const RunStatus& status) override;
  void on_end(const RunStatus& status, const RunResult& result) override;

 private:
  void write(const RunStatus& status);
  std::filesystem::path dir_;
  std::uint64_t fingerprint_;
  double last_checkpoint_ = 0.0;
};

// A distributed evaluator can lose a worker midway through a step, leaving the algorithm
// half-stepped: keeps the state before each step and, when the step is aborted, checkpoints that
// instead and rethrows with where the run can continue from.
class AbortCheckpoint : public RunObserver {
 public:
  AbortCheckpoint(std::filesystem::path dir, std::uint64_t fingerprint);
  void before_step(const RunStatus& status) override;
  void on_step_aborted(const RunStatus& status, const EvaluationAborted& error) override;

 private:
  std::filesystem::path dir_;
  std::uint64_t fingerprint_;
  std::optional<RunSnapshot> before_;
};

}  // namespace qdmeta
