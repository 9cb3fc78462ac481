#pragma once
// summary.json: why a run stopped, its counters, final statistics and speed. Written last and
// atomically, so a summary saying `budget` marks a finished run.
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/io/table.hpp"
#include "qdmeta/run/run_result.hpp"

namespace qdmeta {

struct SummaryRecord {
  const RunResult& result;
  const RunSettings& settings;
  std::string algorithm;
  int threads = 1;
  std::vector<std::pair<std::string, double>> extras;  // Algorithm::summary_extras()
};

// Its keys in order: the run's identity, then the final metrics point (metrics.csv's columns,
// from the same declaration), the algorithm's extras, then the timing.
const Table<SummaryRecord>& summary_head_table();
const Table<SummaryRecord>& summary_tail_table();

void write_summary(const std::filesystem::path& path, const SummaryRecord& record);

// Why the run in `dir` stopped, from its summary.json; nullopt when there is none (a run still
// going, or killed). Throws InputError on an unreadable summary.
std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir);

}  // namespace qdmeta
