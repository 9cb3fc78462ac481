#pragma once
// The observers that log a run as it goes: metrics.csv and meta.csv. A resumed run continues
// both files from the checkpoint's byte counts, so its logs equal an uninterrupted run's.
#include <filesystem>
#include <optional>

#include "qdmeta/io/csv.hpp"
#include "qdmeta/run/run_observer.hpp"

namespace qdmeta {

// metrics.csv: a row at the first generation at or past every `[log] every` evaluations, at
// the budget, and for the last generation when the run ends between two of those.
class MetricsLogger : public RunObserver {
 public:
  // `resume`: continue the file from the checkpoint's cursor instead of starting it anew.
  MetricsLogger(const std::filesystem::path& path, const RunCursor* resume);
  RunVerdict on_start(const RunStatus& status) override;
  RunVerdict after_step(const RunStatus& status) override;
  void on_end(const RunStatus& status, const RunResult& result) override;

 private:
  void log(const RunStatus& status);
  CsvAppender file_;
};

// meta.csv: a row per finished meta-generation, for algorithms with a meta level; the file is
// started at the first one.
class MetaLogger : public RunObserver {
 public:
  MetaLogger(std::filesystem::path path, const RunCursor* resume);
  RunVerdict after_step(const RunStatus& status) override;

 private:
  std::filesystem::path path_;
  std::optional<CsvAppender> file_;
};

}  // namespace qdmeta
