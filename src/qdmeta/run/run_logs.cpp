#include "qdmeta/run/run_logs.hpp"

#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {

MetricsLogger::MetricsLogger(const std::filesystem::path& path, const RunCursor* resume)
    : file_(resume ? CsvAppender(path, metrics_columns(), resume->metrics_bytes, resume->metrics_hash)
                   : CsvAppender(path, metrics_columns())) {}

RunVerdict MetricsLogger::on_start(const RunStatus& status) {
  status.cursor.metrics_bytes = file_.bytes();
  status.cursor.metrics_hash = file_.hash();
  return RunVerdict::kContinue;
}

RunVerdict MetricsLogger::after_step(const RunStatus& status) {
  if (status.evals >= status.cursor.next_log || status.evals >= status.settings.budget) log(status);
  return RunVerdict::kContinue;
}

void MetricsLogger::on_end(const RunStatus& status, const RunResult&) {
  const std::int64_t generation = status.algorithm.generation();
  if (status.cursor.last_logged_generation != generation && generation > 0) log(status);
}

void MetricsLogger::log(const RunStatus& status) {
  file_.row(metrics_table().row(run_point(status.algorithm, status.evals)));
  RunCursor& cursor = status.cursor;
  cursor.metrics_bytes = file_.bytes();
  cursor.metrics_hash = file_.hash();
  cursor.last_logged_generation = status.algorithm.generation();
  while (cursor.next_log <= status.evals) cursor.next_log += status.settings.log_every;
}

MetaLogger::MetaLogger(std::filesystem::path path, const RunCursor* resume) : path_(std::move(path)) {
  if (resume && resume->meta_bytes > 0) file_.emplace(path_, meta_columns(), resume->meta_bytes, resume->meta_hash);
}

RunVerdict MetaLogger::after_step(const RunStatus& status) {
  if (const MetaGenerationRecord* record = status.algorithm.last_meta_record()) {
    if (!file_) file_.emplace(path_, meta_columns());
    file_->row(meta_table().row(MetaPoint{*record, status.algorithm.counters(), status.evals}));
    status.cursor.meta_bytes = file_->bytes();
    status.cursor.meta_hash = file_->hash();
  }
  return RunVerdict::kContinue;
}

}  // namespace qdmeta
