#pragma once
// summary.json: why a run stopped, its counters, final statistics and speed. Written last and
// atomically, so a summary saying `budget` marks a finished run.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
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

// summary.json read back, the one reader of what write_summary wrote: every key in the file's
// order, each value a whole number, a number, text, or null (JSON's word for a number that was
// not finite when written).
using SummaryValue = std::variant<std::monostate, std::int64_t, double, std::string>;

struct RunSummary {
  StopReason stop_reason = StopReason::kBudget;
  std::vector<std::pair<std::string, SummaryValue>> values;
  const SummaryValue* find(std::string_view key) const;
  std::optional<std::int64_t> integer(std::string_view key) const;  // nullopt: absent or not whole
};

// The text of a summary (summary.json, or the "summary" of a kept one, tools/runs.py); `where`
// names it in errors. InputError when it is not a JSON object of numbers and text with a known
// stop_reason.
RunSummary parse_summary(std::string_view text, const std::string& where);

// The summary.json of the run in `dir`; nullopt when there is none (a run still going, or
// killed). InputError naming the file when it is unreadable.
std::optional<RunSummary> read_summary(const std::filesystem::path& dir);
// Its stop reason alone: the 0.2.0 name, kept for one minor version.
std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir);

}  // namespace qdmeta
