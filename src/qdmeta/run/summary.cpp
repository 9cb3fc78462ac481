#include "qdmeta/run/summary.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {

namespace {

Cell text(std::string_view s) { return std::string(s); }

template <class Record>
void add_to_json(nlohmann::ordered_json& j, const Table<Record>& table, const Record& record) {
  for (const auto& column : table.columns())
    std::visit([&](const auto& value) { j[std::string(column.key())] = value; }, column.value(record));
}

}  // namespace

const Table<SummaryRecord>& summary_head_table() {
  static const Table<SummaryRecord> table = {
      {"algorithm", [](const SummaryRecord& r) { return text(r.algorithm); }},
      {"task", [](const SummaryRecord& r) { return text(r.settings.task); }},
      {"stop_reason", [](const SummaryRecord& r) { return text(enum_to_string(kStopReasonNames, r.result.reason)); }},
      {"message", [](const SummaryRecord& r) { return text(r.result.message); }},
      {"seed", [](const SummaryRecord& r) { return Cell(r.settings.seed); }},
      {"budget", [](const SummaryRecord& r) { return Cell(r.settings.budget); }},
      {"budget_counts", [](const SummaryRecord& r) { return text(enum_to_string(kBudgetCountNames, r.settings.counts)); }},
  };
  return table;
}

const Table<SummaryRecord>& summary_tail_table() {
  static const Table<SummaryRecord> table = {
      {"threads", [](const SummaryRecord& r) { return Cell(std::int64_t{r.threads}); }},
      {"wall_seconds", [](const SummaryRecord& r) { return Cell(r.result.wall_seconds); }},
      {"evals_per_second",
       [](const SummaryRecord& r) {
         const double s = r.result.wall_seconds;
         return Cell(s > 0 ? static_cast<double>(r.result.counters.total()) / s : 0.0);
       }},
  };
  return table;
}

void write_summary(const std::filesystem::path& path, const SummaryRecord& record) {
  const RunResult& r = record.result;
  nlohmann::ordered_json j;
  add_to_json(j, summary_head_table(), record);
  add_to_json(j, metrics_table(), RunPoint{r.evals, r.counters, r.generations, r.stats});
  for (const auto& [name, value] : record.extras) j[name] = value;
  add_to_json(j, summary_tail_table(), record);
  write_file_atomic(path, j.dump(2) + "\n");
}

std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir) {
  const auto path = dir / "summary.json";
  if (!path_taken(path)) return std::nullopt;
  const std::string text = read_regular_file(path, kMaxTextFileBytes);
  try {
    const auto j = nlohmann::json::parse(text);
    return enum_from_string(kStopReasonNames, "stop_reason", j.at("stop_reason").get<std::string>());
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{} is unreadable: {}", path.string(), e.what()));
  }
}

}  // namespace qdmeta
