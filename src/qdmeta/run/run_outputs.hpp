#pragma once
// The observer that finishes a run directory: archive.csv, then summary.json (written last: a
// summary saying `budget` marks a finished run), then, for a finished run, the checkpoint goes.
#include <filesystem>

#include "qdmeta/run/run_observer.hpp"

namespace qdmeta {

class RunOutputs : public RunObserver {
 public:
  // `threads`: the evaluator's workers, recorded in the summary.
  RunOutputs(std::filesystem::path dir, int threads) : dir_(std::move(dir)), threads_(threads) {}
  void on_end(const RunStatus& status, const RunResult& result) override;

 private:
  std::filesystem::path dir_;
  int threads_;
};

}  // namespace qdmeta
