#pragma once
// What a run directory holds, read once and handed on: whether there is a run (config.toml),
// whether it finished (summary.json says `budget`), whether it has a checkpoint, and its
// config.toml, parsed at the first use and then kept. `qdmeta resume`, `adapt` and `experiment`
// decide from this one reading instead of probing the files again.
#include <cstdint>
#include <filesystem>
#include <optional>

#include <toml++/toml.h>

#include "qdmeta/run/run_result.hpp"
#include "qdmeta/run/summary.hpp"

namespace qdmeta {

class RunState {
 public:
  // Reads the state of `dir` (a missing directory is an empty one). InputError on an unreadable
  // summary.json, naming it.
  explicit RunState(std::filesystem::path dir);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path config_path() const { return dir_ / "config.toml"; }
  bool has_run() const { return has_config_; }  // config.toml is there
  // summary.json, read once (none while unfinished).
  const std::optional<RunSummary>& summary() const { return summary_; }
  std::optional<StopReason> stop_reason() const { return summary_ ? std::optional(summary_->stop_reason) : std::nullopt; }
  bool finished() const { return stop_reason() == StopReason::kBudget; }
  bool has_checkpoint() const { return has_checkpoint_; }
  // config.toml, parsed at the first call (InputError naming the file when it is damaged).
  const toml::table& config() const;
  // What config.toml's budget.evaluations asks for, or -1.
  std::int64_t budget() const;

 private:
  std::filesystem::path dir_;
  bool has_config_ = false;
  std::optional<RunSummary> summary_;
  bool has_checkpoint_ = false;
  mutable std::optional<toml::table> config_;
};

}  // namespace qdmeta
