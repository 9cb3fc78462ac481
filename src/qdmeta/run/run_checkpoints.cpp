#include "qdmeta/run/run_checkpoints.hpp"

#include <fmt/format.h>

#include <csignal>
#include <cstdlib>
#include <string>

namespace qdmeta {
namespace {

// Test hook: QDMETA_TEST_SIGNAL_AT_CHECKPOINT="N:SIGNAL" makes the process send itself SIGNAL
// (KILL, INT, TERM or STOP) right after it writes its N-th checkpoint of the run, so that a test
// that kills or interrupts a run at a checkpoint needs no race between a timer and the run.
void signal_self_at_checkpoint(std::int64_t checkpoints) {
  static const auto hook = []() -> std::pair<std::int64_t, int> {
    const char* spec = std::getenv("QDMETA_TEST_SIGNAL_AT_CHECKPOINT");
    if (!spec) return {0, 0};
    const std::string s = spec;
    const auto colon = s.find(':');
    const std::string name = colon == std::string::npos ? "" : s.substr(colon + 1);
    const int signal = name == "KILL" ? SIGKILL : name == "INT" ? SIGINT : name == "TERM" ? SIGTERM : name == "STOP" ? SIGSTOP : 0;
    return {std::atoll(s.c_str()), signal};
  }();
  if (hook.second != 0 && checkpoints == hook.first) std::raise(hook.second);
}

}  // namespace

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
  signal_self_at_checkpoint(status.cursor.checkpoints);
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
