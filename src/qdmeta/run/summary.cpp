#include "qdmeta/run/summary.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <limits>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/run/run_tables.hpp"

namespace qdmeta {

namespace {

Cell text(std::string_view s) { return std::string(s); }

constexpr auto kMaxInt64 = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());

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

const SummaryValue* RunSummary::find(std::string_view key) const {
  for (const auto& [name, value] : values)
    if (name == key) return &value;
  return nullptr;
}

std::optional<std::int64_t> RunSummary::integer(std::string_view key) const {
  const SummaryValue* value = find(key);
  if (value == nullptr || !std::holds_alternative<std::int64_t>(*value)) return std::nullopt;
  return std::get<std::int64_t>(*value);
}

RunSummary parse_summary(std::string_view text, const std::string& where) {
  RunSummary summary;
  try {
    const auto j = nlohmann::ordered_json::parse(text);
    if (!j.is_object()) throw InputError("not a JSON object");
    for (const auto& [key, v] : j.items()) {
      SummaryValue value;
      if (v.is_number_integer() && (!v.is_number_unsigned() || v.get<std::uint64_t>() <= kMaxInt64))
        value = v.get<std::int64_t>();
      else if (v.is_number()) value = v.get<double>();
      else if (v.is_string()) value = v.get<std::string>();
      else if (!v.is_null()) throw InputError(fmt::format("'{}' holds neither a number nor text", key));
      summary.values.emplace_back(key, std::move(value));
    }
    const SummaryValue* reason = summary.find("stop_reason");
    if (reason == nullptr || !std::holds_alternative<std::string>(*reason))
      throw InputError("stop_reason is missing or not text");
    summary.stop_reason = enum_from_string(kStopReasonNames, "stop_reason", std::get<std::string>(*reason));
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{} is unreadable: {}", where, e.what()));
  }
  return summary;
}

std::optional<RunSummary> read_summary(const std::filesystem::path& dir) {
  const auto path = dir / "summary.json";
  if (!path_taken(path)) return std::nullopt;
  return parse_summary(read_regular_file(path, kMaxTextFileBytes), path.string());
}

std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir) {
  const std::optional<RunSummary> summary = read_summary(dir);
  return summary ? std::optional(summary->stop_reason) : std::nullopt;
}

}  // namespace qdmeta
