#include "qdmeta/experiment/run_checkpoints.hpp"

#include <fmt/format.h>

namespace qdmeta {

CheckpointWriter::CheckpointWriter(std::filesystem::path dir, std::uint64_t fingerprint)
    : dir_(std::move(dir)), fingerprint_(fingerprint) {}

RunVerdict CheckpointWriter::on_start(const RunStatus& status) {
  last_checkpoint_ = status.clock.seconds();
  return RunVerdict::kContinue;
}

RunVerdict CheckpointWriter::after_step(const RunStatus& status) {
  const bool due =
      status.cursor.checkpoints == 0 || status.clock.seconds() - last_checkpoint_ >= status.settings.checkpoint_every;
  if (status.evals < status.settings.budget && due) {
    write(status);
    last_checkpoint_ = status.clock.seconds();
  }
  return RunVerdict::kContinue;
}

void CheckpointWriter::on_end(const RunStatus& status, const RunResult& result) {
  if (result.reason == StopReason::kInterrupted) write(status);
}

void CheckpointWriter::write(const RunStatus& status) {
  status.cursor.wall_seconds = status.clock.seconds();
  ++status.cursor.checkpoints;
  write_checkpoint(dir_, fingerprint_, status.cursor, status.algorithm);
}

AbortCheckpoint::AbortCheckpoint(std::filesystem::path dir, std::uint64_t fingerprint)
    : dir_(std::move(dir)), fingerprint_(fingerprint) {}

void AbortCheckpoint::before_step(const RunStatus& status) {
  RunCursor cursor = status.cursor;
  cursor.wall_seconds = status.clock.seconds();
  ++cursor.checkpoints;
  before_ = take_snapshot(cursor, status.algorithm);
}

void AbortCheckpoint::on_step_aborted(const RunStatus& status, const EvaluationAborted& error) {
  write_checkpoint(dir_, fingerprint_, *before_);
  throw EvaluationAborted(
      fmt::format("{}; checkpoint written at {} evaluations (the last finished step)", error.what(), status.evals));
}

}  // namespace qdmeta
