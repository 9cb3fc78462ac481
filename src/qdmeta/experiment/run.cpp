#include "qdmeta/experiment/run.hpp"

#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"

namespace qdmeta {

const std::vector<std::string>& metrics_columns() {
  static const std::vector<std::string> columns = {"evals",     "evals_bottom", "evals_meta", "generation",
                                                   "num_elites", "coverage",     "qd_score",   "norm_qd_score",
                                                   "obj_max",   "obj_mean"};
  return columns;
}

const std::vector<std::string>& meta_columns() {
  static const std::vector<std::string> columns = {
      "meta_generation",   "evals",           "evals_bottom", "evals_meta", "meta_fitness_best",
      "meta_fitness_mean", "meta_fitness_sd", "generations",  "states"};
  return columns;
}

namespace {

std::vector<std::string> metrics_row(const Algorithm& algorithm, std::int64_t evals) {
  const ArchiveStats s = algorithm.stats();
  const EvaluationCounters c = algorithm.counters();
  return {fmt::format("{}", evals),        fmt::format("{}", c.bottom),     fmt::format("{}", c.meta),
          fmt::format("{}", algorithm.generation()), fmt::format("{}", s.num_elites), fmt::format("{}", s.coverage),
          fmt::format("{}", s.qd_score),   fmt::format("{}", s.norm_qd_score), fmt::format("{}", s.obj_max),
          fmt::format("{}", s.obj_mean)};
}

std::vector<std::string> meta_row(const MetaGenerationRecord& m, const EvaluationCounters& c, std::int64_t evals) {
  return {fmt::format("{}", m.meta_generation),   fmt::format("{}", evals),
          fmt::format("{}", c.bottom),            fmt::format("{}", c.meta),
          fmt::format("{}", m.meta_fitness_best), fmt::format("{}", m.meta_fitness_mean),
          fmt::format("{}", m.meta_fitness_sd),   fmt::format("{}", m.generations),
          fmt::format("{}", m.states)};
}

void write_summary(const std::filesystem::path& path, const RunResult& r, const RunSettings& settings,
                   const Algorithm& algorithm, int threads) {
  nlohmann::ordered_json j;
  j["algorithm"] = algorithm.name();
  j["stop_reason"] = std::string(enum_to_string(kStopReasonNames, r.reason));
  j["message"] = r.message;
  j["seed"] = settings.seed;
  j["budget"] = settings.budget;
  j["budget_counts"] = std::string(enum_to_string(kBudgetCountNames, settings.counts));
  j["evals"] = r.evals;
  j["evals_bottom"] = r.counters.bottom;
  j["evals_meta"] = r.counters.meta;
  j["generations"] = r.generations;
  j["num_elites"] = r.stats.num_elites;
  j["coverage"] = r.stats.coverage;
  j["qd_score"] = r.stats.qd_score;
  j["norm_qd_score"] = r.stats.norm_qd_score;
  j["obj_max"] = r.stats.obj_max;
  j["obj_mean"] = r.stats.obj_mean;
  for (const auto& [name, value] : algorithm.summary_extras()) j[name] = value;
  j["threads"] = threads;
  j["wall_seconds"] = r.wall_seconds;
  j["evals_per_second"] = r.wall_seconds > 0 ? static_cast<double>(r.counters.total()) / r.wall_seconds : 0.0;
  write_file_atomic(path, j.dump(2) + "\n");
}

}  // namespace

std::optional<StopReason> stop_reason_of(const std::filesystem::path& dir) {
  const auto path = dir / "summary.json";
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(in);
    return enum_from_string(kStopReasonNames, "stop_reason", j.at("stop_reason").get<std::string>());
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{} is unreadable: {}", path.string(), e.what()));
  }
}

RunResult run_to_budget(Algorithm& algorithm, Evaluator& evaluator, const RunSettings& settings,
                        const std::filesystem::path& out_dir, const ProgressCallback& progress,
                        const std::atomic<bool>* stop, const RunCursor* resume) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const double before = resume ? resume->wall_seconds : 0.0;
  const auto elapsed = [&] { return before + std::chrono::duration<double>(Clock::now() - start).count(); };

  RunCursor cursor = resume ? *resume : RunCursor{};
  CsvAppender metrics = resume ? CsvAppender(out_dir / "metrics.csv", metrics_columns(), resume->metrics_bytes)
                               : CsvAppender(out_dir / "metrics.csv", metrics_columns());
  std::optional<CsvAppender> meta;  // meta.csv, for algorithms with a meta level
  if (resume && resume->meta_bytes > 0) meta.emplace(out_dir / "meta.csv", meta_columns(), resume->meta_bytes);
  const auto checkpoint = [&] {
    cursor.metrics_bytes = metrics.bytes();
    cursor.meta_bytes = meta ? meta->bytes() : 0;
    cursor.wall_seconds = elapsed();
    ++cursor.checkpoints;
    write_checkpoint(out_dir, settings.fingerprint, cursor, algorithm);
  };
  double last_checkpoint = elapsed();

  const bool guard = evaluator.may_abort() && algorithm.checkpointable();
  RunResult result;
  std::int64_t evals = settings.evals(algorithm.counters());
  while (evals < settings.budget) {
    if (stop && stop->load()) {
      result.reason = StopReason::kInterrupted;
      break;
    }
    // A distributed evaluator can lose a worker midway through a step, leaving the algorithm
    // half-stepped: keep the state before the step, and on failure checkpoint that instead.
    std::optional<RunSnapshot> before;
    if (guard) {
      RunCursor c = cursor;
      c.metrics_bytes = metrics.bytes();
      c.meta_bytes = meta ? meta->bytes() : 0;
      c.wall_seconds = elapsed();
      c.checkpoints = cursor.checkpoints + 1;
      before = take_snapshot(c, algorithm);
    }
    try {
      algorithm.step(evaluator);
    } catch (const EvaluationAborted& e) {
      if (!guard) throw;
      write_checkpoint(out_dir, settings.fingerprint, *before);
      throw EvaluationAborted(fmt::format("{}; checkpoint written at {} evaluations (the last finished step)", e.what(),
                                          evals));
    }
    evals = settings.evals(algorithm.counters());
    if (const MetaGenerationRecord* record = algorithm.last_meta_record()) {
      if (!meta) meta.emplace(out_dir / "meta.csv", meta_columns());
      meta->row(meta_row(*record, algorithm.counters(), evals));
    }
    if (evals >= cursor.next_log || evals >= settings.budget) {
      metrics.row(metrics_row(algorithm, evals));
      cursor.last_logged_generation = algorithm.generation();
      while (cursor.next_log <= evals) cursor.next_log += settings.log_every;
    }
    // The first checkpoint follows the first step, so that a run killed early can be resumed too.
    const bool due = cursor.checkpoints == 0 || elapsed() - last_checkpoint >= settings.checkpoint_every;
    if (algorithm.checkpointable() && evals < settings.budget && due) {
      checkpoint();
      last_checkpoint = elapsed();
    }
    if (progress) progress({evals, settings.budget, algorithm.generation(), elapsed(), &algorithm});
  }
  // An interrupted run keeps a checkpoint taken before its closing metrics row, so that a
  // resumed run's logs continue exactly as an uninterrupted run's would.
  if (result.reason == StopReason::kInterrupted && algorithm.checkpointable()) checkpoint();
  if (cursor.last_logged_generation != algorithm.generation() && algorithm.generation() > 0)
    metrics.row(metrics_row(algorithm, evals));

  result.counters = algorithm.counters();
  result.evals = evals;
  result.generations = algorithm.generation();
  result.stats = algorithm.stats();
  write_elites_csv(out_dir / "archive.csv", algorithm.elites());
  result.wall_seconds = elapsed();
  result.message = result.reason == StopReason::kBudget
                       ? fmt::format("reached the budget of {} evaluations ({} spent)", settings.budget, evals)
                       : fmt::format("interrupted after {} of {} evaluations", evals, settings.budget);
  write_summary(out_dir / "summary.json", result, settings, algorithm, evaluator.workers());
  if (result.reason == StopReason::kBudget) std::filesystem::remove(out_dir / kCheckpointFile);
  return result;
}

}  // namespace qdmeta
