// The run driver: budget semantics, metrics rows, interruption, files written, observers.
#include "qdmeta/run/run.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "own_temp_path.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = test::own_temp_path("run_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

BuiltRun small_run(std::int64_t evals, std::int64_t log_every) {
  toml::table config = load_toml(fs::path(QDMETA_SOURCE_DIR) / "configs/rastrigin/map-elites.toml");
  config.insert_or_assign("log", toml::table{{"every", log_every}});
  return build_run(config, "map-elites.toml", {std::nullopt, evals});
}

std::vector<std::string> lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

TEST(Run, StopsAtTheFirstGenerationAtOrPastTheBudget) {
  const fs::path dir = fresh_dir("budget");
  BuiltRun built = small_run(10'001, 1000);
  SerialEvaluator evaluator;
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir);
  EXPECT_EQ(r.reason, StopReason::kBudget);
  EXPECT_EQ(r.evals, 10'400);  // 2,000 + 21 x 400: the overshoot is real and reported
  EXPECT_EQ(r.generations, 22);
  const auto rows = lines(dir / "metrics.csv");
  EXPECT_EQ(rows.front(), "evals,evals_bottom,evals_meta,generation,num_elites,coverage,qd_score,norm_qd_score,obj_max,obj_mean");
  EXPECT_TRUE(rows.back().starts_with("10400,10400,0,22,"));
  EXPECT_TRUE(fs::exists(dir / "archive.csv"));
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "archive.csv.tmp"));
  EXPECT_EQ(read_elites_csv(dir / "archive.csv").size(), r.stats.num_elites);
}

TEST(Run, LogsARowPerPeriodAndTheLastGeneration) {
  const fs::path dir = fresh_dir("period");
  BuiltRun built = small_run(20'000, 4000);
  SerialEvaluator evaluator;
  run_to_budget(*built.algorithm, evaluator, built.settings, dir);
  const auto rows = lines(dir / "metrics.csv");
  // Rows at the first generation at or past 0, 4000, 8000, 12000, 16000, 20000.
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_TRUE(rows[1].starts_with("2000,"));
  EXPECT_TRUE(rows[2].starts_with("4000,"));
  EXPECT_TRUE(rows[6].starts_with("20000,"));
}

TEST(Run, InterruptionStopsAtAGenerationBoundaryAndStillWritesTheArchive) {
  const fs::path dir = fresh_dir("interrupt");
  BuiltRun built = small_run(1'000'000, 10000);
  SerialEvaluator evaluator;
  std::atomic<bool> stop{false};
  const RunResult r = run_to_budget(
      *built.algorithm, evaluator, built.settings, dir, [&](const RunProgress& p) { stop = p.generation >= 5; }, &stop);
  EXPECT_EQ(r.reason, StopReason::kInterrupted);
  EXPECT_EQ(r.generations, 5);
  EXPECT_EQ(read_elites_csv(dir / "archive.csv").size(), r.stats.num_elites);
  EXPECT_TRUE(lines(dir / "metrics.csv").back().starts_with("3600,"));
}

// A library user's observer: records every hook it is told, in order.
struct Recorder : RunObserver {
  std::vector<std::string>* log;
  std::string name;
  std::vector<std::int64_t> evals_after_step;
  std::int64_t stop_at_generation = -1;
  Recorder(std::vector<std::string>* l, std::string n) : log(l), name(std::move(n)) {}
  RunVerdict on_start(const RunStatus& s) override {
    log->push_back(fmt::format("{} start {}", name, s.evals));
    return RunVerdict::kContinue;
  }
  void before_step(const RunStatus&) override { log->push_back(name + " before"); }
  RunVerdict after_step(const RunStatus& s) override {
    evals_after_step.push_back(s.evals);
    log->push_back(name + " after");
    return s.algorithm.generation() == stop_at_generation ? RunVerdict::kStop : RunVerdict::kContinue;
  }
  void on_end(const RunStatus& s, const RunResult& r) override {
    log->push_back(fmt::format("{} end {} {}", name, s.evals, enum_to_string(kStopReasonNames, r.reason)));
  }
};

TEST(RunObservers, AUsersObserverSeesEveryStepAfterTheStandardFilesAreWritten) {
  const fs::path dir = fresh_dir("observer");
  BuiltRun built = small_run(10'001, 1000);
  SerialEvaluator evaluator;
  std::vector<std::string> log;
  Recorder recorder(&log, "r");
  RunOptions options;
  options.observers = {&recorder};
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir, options);
  ASSERT_EQ(recorder.evals_after_step.size(), static_cast<std::size_t>(r.generations));
  for (std::size_t g = 0; g < recorder.evals_after_step.size(); ++g)
    EXPECT_EQ(recorder.evals_after_step[g], g == 0 ? 2000 : 2000 + 400 * static_cast<std::int64_t>(g));
  EXPECT_EQ(log.front(), "r start 0");
  EXPECT_EQ(log.back(), "r end 10400 budget");
  EXPECT_EQ(log.size(), 2 + 2 * static_cast<std::size_t>(r.generations));
  EXPECT_TRUE(lines(dir / "metrics.csv").back().starts_with("10400,"));
  EXPECT_FALSE(fs::exists(dir / kCheckpointFile)) << "a finished run keeps no checkpoint";
}

TEST(RunObservers, AnObserversStopEndsTheRunInterruptedWithACheckpointBeforeTheClosingRow) {
  const fs::path dir = fresh_dir("observer_stop");
  BuiltRun built = small_run(1'000'000, 10'000);
  SerialEvaluator evaluator;
  std::vector<std::string> log;
  Recorder recorder(&log, "r");
  recorder.stop_at_generation = 5;
  RunOptions options;
  options.observers = {&recorder};
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir, options);
  EXPECT_EQ(r.reason, StopReason::kInterrupted);
  EXPECT_EQ(r.generations, 5);
  const auto rows = lines(dir / "metrics.csv");
  EXPECT_TRUE(rows.back().starts_with("3600,"));  // the closing row of the last generation
  // The checkpoint was taken before that row: a resume cuts it and logs on as if never stopped.
  BuiltRun again = small_run(1'000'000, 10'000);
  const RunCursor cursor = read_checkpoint(dir, again.settings.fingerprint, *again.algorithm);
  EXPECT_EQ(again.algorithm->generation(), 5);
  EXPECT_EQ(cursor.metrics_bytes, fs::file_size(dir / "metrics.csv") - rows.back().size() - 1);
  EXPECT_EQ(cursor.last_logged_generation, 1);
}

TEST(RunObservers, TheBudgetWinsOverAStopAtTheLastStep) {
  const fs::path dir = fresh_dir("observer_budget_wins");
  BuiltRun built = small_run(10'001, 1000);
  SerialEvaluator evaluator;
  std::vector<std::string> log;
  Recorder recorder(&log, "r");
  recorder.stop_at_generation = 22;  // the step that reaches the budget
  RunOptions options;
  options.observers = {&recorder};
  EXPECT_EQ(run_to_budget(*built.algorithm, evaluator, built.settings, dir, options).reason, StopReason::kBudget);
}

TEST(RunObservers, ObserversAreToldInOrderAndEndInReverseOrder) {
  BuiltRun built = small_run(2'400, 1000);  // two generations
  SerialEvaluator evaluator;
  std::vector<std::string> log;
  Recorder a(&log, "a"), b(&log, "b");
  std::vector<RunObserver*> observers = {&a, &b};
  const RunResult r = drive_run(*built.algorithm, evaluator, built.settings, observers);
  EXPECT_EQ(r.generations, 2);
  EXPECT_EQ(log, (std::vector<std::string>{"a start 0", "b start 0", "a before", "b before", "a after", "b after",
                                           "a before", "b before", "a after", "b after", "b end 2400 budget",
                                           "a end 2400 budget"}));
}

TEST(RunObservers, AFlagSetBeforeTheStartStopsTheRunBeforeItsFirstStep) {
  const fs::path dir = fresh_dir("stopped_before_start");
  BuiltRun built = small_run(10'000, 1000);
  SerialEvaluator evaluator;
  const std::atomic<bool> stop{true};
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir, {}, &stop);
  EXPECT_EQ(r.reason, StopReason::kInterrupted);
  EXPECT_EQ(r.generations, 0);
  EXPECT_EQ(lines(dir / "metrics.csv").size(), 1u);  // the header only
  EXPECT_TRUE(fs::exists(dir / kCheckpointFile));
}

// An evaluator that loses a "worker" at its n-th batch, as a distributed one can.
class AbortingEvaluator : public Evaluator {
 public:
  explicit AbortingEvaluator(int abort_at) : abort_at_(abort_at) {}
  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    if (++calls_ == abort_at_) throw EvaluationAborted("worker lost");
    serial_.evaluate(task, genotypes, out);
  }
  int workers() const override { return 1; }
  bool may_abort() const override { return true; }

 private:
  SerialEvaluator serial_;
  int abort_at_;
  int calls_ = 0;
};

TEST(RunObservers, AnAbortedStepLeavesTheCheckpointOfTheLastFinishedStep) {
  const fs::path dir = fresh_dir("aborted");
  BuiltRun built = small_run(1'000'000, 1000);
  AbortingEvaluator evaluator(4);  // steps 1-3 finish, the 4th is aborted midway
  try {
    run_to_budget(*built.algorithm, evaluator, built.settings, dir);
    FAIL() << "the aborted step did not stop the run";
  } catch (const EvaluationAborted& e) {
    EXPECT_STREQ(e.what(), "worker lost; checkpoint written at 2800 evaluations (the last finished step)");
  }
  BuiltRun again = small_run(1'000'000, 1000);
  const RunCursor cursor = read_checkpoint(dir, again.settings.fingerprint, *again.algorithm);
  EXPECT_EQ(again.algorithm->generation(), 3);
  EXPECT_EQ(cursor.metrics_bytes, fs::file_size(dir / "metrics.csv"));
  EXPECT_EQ(cursor.checkpoints, 2);  // the one after the first step, then this one
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << "an aborted run must not look finished";
}

// An evaluator whose n-th batch is stopped by the user midway (Ctrl-C inside a Python task).
class InterruptingEvaluator : public Evaluator {
 public:
  explicit InterruptingEvaluator(int interrupt_at) : interrupt_at_(interrupt_at) {}
  void evaluate(const Task& task, GenotypeView genotypes, EvaluationView out) override {
    if (++calls_ == interrupt_at_) throw StepInterrupted("Ctrl-C");
    serial_.evaluate(task, genotypes, out);
  }
  int workers() const override { return 1; }

 private:
  SerialEvaluator serial_;
  int interrupt_at_;
  int calls_ = 0;
};

TEST(RunObservers, AStepInterruptedMidwayEndsTheRunAtTheLastBoundaryWithItsFilesThenResumesToTheSameBits) {
  const fs::path straight = fresh_dir("step_interrupted_straight"), dir = fresh_dir("step_interrupted");
  {
    BuiltRun built = small_run(6'000, 1000);
    SerialEvaluator evaluator;
    run_to_budget(*built.algorithm, evaluator, built.settings, straight);
  }
  BuiltRun built = small_run(6'000, 1000);
  InterruptingEvaluator evaluator(4);  // steps 1-3 finish, the 4th is stopped midway
  EXPECT_THROW(run_to_budget(*built.algorithm, evaluator, built.settings, dir), StepInterrupted);
  EXPECT_EQ(built.algorithm->generation(), 3);
  EXPECT_FALSE(built.algorithm->step_in_progress());
  std::ifstream summary_file(dir / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["stop_reason"], "interrupted");
  EXPECT_EQ(summary["evals"], 2800);
  EXPECT_EQ(read_elites_csv(dir / "archive.csv").size(), built.algorithm->stats().num_elites);
  BuiltRun again = small_run(6'000, 1000);
  const RunCursor cursor = read_checkpoint(dir, again.settings.fingerprint, *again.algorithm);
  EXPECT_EQ(again.algorithm->generation(), 3);
  SerialEvaluator serial;
  RunOptions options;
  options.resume = &cursor;
  EXPECT_EQ(run_to_budget(*again.algorithm, serial, again.settings, dir, options).reason, StopReason::kBudget);
  for (const char* f : {"archive.csv", "metrics.csv"}) {
    std::ifstream a(dir / f), b(straight / f);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(a), {}), std::string(std::istreambuf_iterator<char>(b), {}))
        << f;
  }
}

TEST(RunSummary, KeysKeepTheirHistoricalOrderAndAgreeWithTheResult) {
  const fs::path dir = fresh_dir("summary");
  BuiltRun built = small_run(10'001, 1000);
  SerialEvaluator evaluator;
  const RunResult r = run_to_budget(*built.algorithm, evaluator, built.settings, dir);
  std::ifstream in(dir / "summary.json");
  const auto j = nlohmann::ordered_json::parse(in);
  std::vector<std::string> keys;
  for (const auto& item : j.items()) keys.push_back(item.key());
  EXPECT_EQ(keys, (std::vector<std::string>{"algorithm", "task", "stop_reason", "message", "seed", "budget", "budget_counts",
                                            "evals", "evals_bottom", "evals_meta", "generations", "num_elites",
                                            "coverage", "qd_score", "norm_qd_score", "obj_max", "obj_mean", "threads",
                                            "wall_seconds", "evals_per_second"}));
  EXPECT_EQ(j["task"], "rastrigin");
  EXPECT_EQ(j["stop_reason"], "budget");
  EXPECT_EQ(j["evals"], 10'400);
  EXPECT_EQ(j["generations"], r.generations);
  EXPECT_EQ(j["num_elites"], r.stats.num_elites);
  EXPECT_EQ(j["qd_score"].get<double>(), r.stats.qd_score);
  EXPECT_EQ(j["message"], r.message);
  EXPECT_EQ(read_summary(dir)->stop_reason, StopReason::kBudget);
}

}  // namespace
}  // namespace qdmeta
