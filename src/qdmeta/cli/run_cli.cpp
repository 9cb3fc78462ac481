// The qdmeta command line (run_cli.hpp): parse, build from the config, call the library. Every
// failure is one line on stderr and exit status 2.
#include "qdmeta/cli/run_cli.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string_view>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/cli/distribution.hpp"
#include "qdmeta/cli/distribution_factory.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/exit_status.hpp"
#include "qdmeta/core/notice.hpp"
#include "qdmeta/core/one_line.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/experiment/adaptation.hpp"
#include "qdmeta/experiment/experiment.hpp"
#include "qdmeta/experiment/kept_runs.hpp"
#include "qdmeta/experiment/test_phase.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/io/run_lock.hpp"
#include "qdmeta/io/subprocess.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"
#include "qdmeta/run/run.hpp"
#include "qdmeta/run/run_directory.hpp"

namespace qdmeta {
namespace fs = std::filesystem;
namespace {

int parse_and_run(int argc, char** argv);

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

Distribution* g_distribution = nullptr;  // set by run_cli_with_tools for its lifetime

std::string human(double x) {
  if (x >= 1e9) return fmt::format("{:.2f}G", x / 1e9);
  if (x >= 1e6) return fmt::format("{:.2f}M", x / 1e6);
  if (x >= 1e3) return fmt::format("{:.1f}k", x / 1e3);
  return fmt::format("{:.0f}", x);
}

// A single refreshing line on a terminal; one line per 10% of the budget otherwise.
ProgressCallback make_progress(bool quiet) {
  if (quiet) return {};
  const bool tty = isatty(fileno(stdout)) != 0;
  auto last = std::make_shared<double>(-1.0);
  auto last_decile = std::make_shared<std::int64_t>(0);
  return [tty, last, last_decile](const RunProgress& p) {
    const double fraction = std::min(1.0, static_cast<double>(p.evals) / static_cast<double>(p.budget));
    const std::int64_t decile = static_cast<std::int64_t>(fraction * 10);
    const bool due = tty ? p.wall_seconds - *last >= 0.25 : decile > *last_decile;
    if (!due) return;
    *last = p.wall_seconds;
    *last_decile = decile;
    const ArchiveStats s = p.algorithm->stats();
    const double rate = p.wall_seconds > 0 ? static_cast<double>(p.algorithm->counters().total()) / p.wall_seconds : 0;
    const double eta = fraction > 0 ? p.wall_seconds * (1 - fraction) / fraction : 0;
    const std::string elites = s.num_elites == 0 ? std::string("no elite yet")
                                                 : fmt::format("elites {}  best {:.4g}  mean {:.4g}", s.num_elites,
                                                               s.obj_max, s.obj_mean);
    std::string line = fmt::format("{:>5.1f}%  {} / {} evals  {} evals/s  {}  ETA {:.0f} s", 100 * fraction, p.evals,
                                   p.budget, human(rate), elites, eta);
    if (tty) fmt::print("\r\033[K{}", line);
    else fmt::print("{}\n", line);
    std::fflush(stdout);
  };
}

// A write that failed (the file size limit, a full disk): the last checkpoint still stands.
Error write_failed(const Error& e, const fs::path& out, bool end_progress_line) {
  if (end_progress_line) fmt::print("\n");
  if (!fs::exists(out / kCheckpointFile)) return e;
  return Error(fmt::format("{}: continue the run from its last checkpoint with: qdmeta resume --out {}", e.what(),
                           out.string()));
}

// A task's own code threw during a step: one line naming the tasks, the generation and what the
// run kept, and its own exit status, so that a script can tell it from a config error (2).
int task_failed(const std::exception& e, const BuiltRun& built, const fs::path& out, bool end_progress_line) {
  if (end_progress_line) fmt::print("\n");
  std::fflush(stdout);
  // TaskFailed names its task and row; another exception (from a meta-objective's or operator's
  // own code) names every task the run evaluates.
  std::string what = e.what();
  if (dynamic_cast<const TaskFailed*>(&e) == nullptr) {
    std::vector<std::string> names;
    for (const Task& t : built.evaluation_tasks) names.push_back(fmt::format("'{}'", t.name()));
    what = fmt::format(" (task {}): {}", fmt::join(names, ", "), what);
  } else {
    what = ": " + what;
  }
  const std::string kept =
      fs::exists(out / kCheckpointFile)
          ? fmt::format("its last checkpoint is kept: fix the task, then continue with: qdmeta resume --out {}",
                        out.string())
          : fmt::format("no checkpoint was written yet: fix the task, then run it again into {}", out.string());
  fmt::print(stderr, "qdmeta: error: {}\n",
             one_line(fmt::format("evaluation failed in generation {} of the run{}; {}",
                                  built.algorithm->generation() + 1, what, kept)));
  return kExitEvaluationFailed;
}

// Runs (or continues) a built run to its budget with progress and a closing summary.
int execute(BuiltRun& built, const fs::path& out, int threads, bool quiet, const RunCursor* resume) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  Distribution& d = *g_distribution;
  auto evaluator = d.make_evaluator(built, threads, &g_stop);
  const bool tty = isatty(fileno(stdout)) != 0;
  const std::string where = d.ranks() > 1 ? fmt::format("{} MPI ranks x {} thread{}", d.ranks(), threads,
                                                           threads > 1 ? "s" : "")
                                            : fmt::format("{} threads", evaluator->workers());
  if (!quiet)
    fmt::print("qdmeta {}: {} on {}, seed {}, budget {} evaluations -> {}\n", kVersion, built.settings.algorithm, where,
               built.settings.seed, built.settings.budget, out.string());
  RunResult r;
  try {
    r = run_to_budget(*built.algorithm, *evaluator, built.settings, out, make_progress(quiet), &g_stop, resume);
  } catch (const InputError&) {
    throw;
  } catch (const StepInterrupted&) {
    throw;
  } catch (const TaskFailed& e) {
    const int status = task_failed(e, built, out, tty && !quiet);
    d.release_survivors();
    return status;
  } catch (const EvaluationAborted& e) {
    // Printed here, not by main: this path must stay one line and finish before mpirun's SIGKILL.
    const std::string who = d.silent_ranks();
    if (tty && !quiet) fmt::print("\n");
    std::fflush(stdout);
    fmt::print(stderr, "qdmeta: error: {}\n",
               one_line(fmt::format("{}{}: continue it with: qdmeta resume --out {}", who, e.what(), out.string())));
    d.release_survivors();
    return who.empty() ? kExitInterrupted : kExitRankFailed;
  } catch (const Error& e) {
    throw write_failed(e, out, tty && !quiet);
  } catch (const std::bad_alloc&) {
    throw;  // main names the memory the config asks for
  } catch (const std::exception& e) {
    // Not qdmeta's own: a task's code threw (the step was undone, its files are as before it).
    const int status = task_failed(e, built, out, tty && !quiet);
    d.release_survivors();
    return status;
  }
  if (r.reason == StopReason::kInterrupted) {
    if (const std::string who = d.silent_ranks(); !who.empty()) {
      if (tty && !quiet) fmt::print("\n");
      std::fflush(stdout);
      fmt::print(stderr, "qdmeta: error: {}\n",
                 one_line(fmt::format("{}the run stopped after {} evaluations with a checkpoint: continue it with: "
                                      "qdmeta resume --out {}", who, r.evals, out.string())));
      d.release_survivors();
      return kExitRankFailed;
    }
  }
  if (!quiet) {
    if (tty) fmt::print("\n");
    // An empty archive has no best or mean: said in words, not as the zeros its statistics hold.
    const std::string archive =
        r.stats.num_elites == 0
            ? std::string("the archive is empty (no elite, so no best or mean)")
            : fmt::format("{} elites, coverage {:.4f}, best {:.6g}, mean {:.6g}, QD-score {:.6g}", r.stats.num_elites,
                          r.stats.coverage, r.stats.obj_max, r.stats.obj_mean, r.stats.qd_score);
    fmt::print("{}: {} evaluations in {:.2f} s ({} evals/s); {}\nresults: {}\n", r.message, r.counters.total(),
               r.wall_seconds, human(r.wall_seconds > 0 ? static_cast<double>(r.counters.total()) / r.wall_seconds : 0),
               archive, out.string());
    if (r.reason == StopReason::kInterrupted && built.algorithm->checkpointable())
      fmt::print("continue it with: qdmeta resume --out {}\n", out.string());
  }
  if (r.stats.num_elites == 0 && r.counters.total() > 0)
    fmt::print(stderr, "qdmeta: warning: no solution was valid in {} evaluations, so the archive is empty (its best "
                       "and mean are not defined): a task marks a solution valid by setting its row's valid flag\n",
               r.counters.total());
  d.release_survivors();
  return r.reason == StopReason::kInterrupted ? kExitInterrupted : 0;
}

struct RunArgs {
  std::string config;
  std::string out;
  std::optional<std::uint64_t> seed;
  std::optional<std::int64_t> evals;
  int threads = 0;
  bool overwrite = false;
  bool quiet = false;
};

int command_run(const RunArgs& a) {
  const toml::table config = load_toml(a.config);
  BuiltRun built = build_run(config, a.config, {a.seed, a.evals});
  // The condition's fingerprint, as an experiment's plan.tsv holds it (not this seed's resolution).
  const std::string fingerprint = resolve_condition(config, a.config, a.evals).fingerprint;
  const RunLock lock(a.out, RunLock::Mode::kExclusive, RunLock::Missing::kCreate);
  start_run_directory(a.out, built, a.config, a.threads, a.overwrite, fingerprint);
  return execute(built, a.out, a.threads, a.quiet, nullptr);
}

struct ResumeArgs {
  std::string out;
  int threads = 0;
  bool quiet = false;
};

// Continues a run from its checkpoint with the resolved config it wrote: to the same result
// as if it had never stopped.
int command_resume(const ResumeArgs& a) {
  const RunLock lock(a.out, RunLock::Mode::kExclusive);
  ResumableRun r = open_for_resume(a.out);
  if (!a.quiet)
    fmt::print("resuming from checkpoint {} at {} evaluations, {:.1f} s into the run\n", r.cursor.checkpoints,
               r.built.settings.evals(r.built.algorithm->counters()), r.cursor.wall_seconds);
  return execute(r.built, a.out, a.threads, a.quiet, &r.cursor);
}

struct AdaptArgs {
  std::string run;
  std::string test;
  std::optional<std::int64_t> budget;
  std::optional<std::int64_t> solutions;
  std::optional<std::uint64_t> seed;
  int threads = 0;
  bool quiet = false;
};

// The test phase on a finished run: random search over its archive under unseen test functions.
int command_adapt(const AdaptArgs& a) {
  const RunLock lock(a.run, RunLock::Mode::kShared);  // test phases may run side by side, not beside a writer
  auto evaluator = make_evaluator(a.threads);
  if (a.test == "generalisation") {
    if (a.budget) throw InputError("--budget does not apply to --test generalisation (it scores the whole archive)");
    const GeneralisationReport g =
        generalise_run(RunState(a.run), a.seed, *evaluator, a.solutions ? std::optional<Index>(*a.solutions) : std::nullopt);
    if (!a.quiet) {
      const Index scored = g.rows.empty() ? g.archive_size : g.rows.front().solutions;
      fmt::print("test 'generalisation': {} of {} archive solutions, mean score per group (+- SE over environments):\n",
                 scored, g.archive_size);
      for (const auto& row : g.rows)
        fmt::print("  {:<18} {:>3} environments: {:.6g} +- {:.3g}\n", row.group, row.environments, row.mean, row.se);
      fmt::print("results: {}\n", g.file.string());
    }
    return 0;
  }
  if (a.solutions) throw InputError("--solutions applies to --test generalisation only");
  const AdaptationReport r = adapt_run(RunState(a.run), a.test, a.budget ? std::optional<Index>(*a.budget) : std::nullopt, a.seed,
                                       *evaluator);
  if (!a.quiet)
    fmt::print("test '{}': {} functions x {} evaluations over {} archive solutions; best after 1: {:.6g} +- {:.3g}, "
               "after {}: {:.6g} +- {:.3g} (mean +- SE over functions)\nresults: {}\n",
               a.test, r.functions, r.budget, r.archive_size, r.curve.best_mean.front(), r.curve.best_se.front(),
               r.budget, r.curve.best_mean.back(), r.curve.best_se.back(), r.file.string());
  return 0;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += fmt::format("{}{}", out.empty() ? "" : ", ", n);
  return out;
}

struct ExperimentArgs {
  std::string config;
  std::string out;
  std::optional<int> replicates;
  std::optional<std::string> seeds;      // a range of the replicates, "A-B" or "A"
  std::optional<std::string> conditions; // condition directory names, "a,b"
  std::optional<std::string> summaries;  // where each finished run's summary goes
  std::optional<std::int64_t> evals;
  int threads = 0;
  bool quiet = false;
  bool no_report = false;
  bool plan = false;
  bool restart_changed = false;
};

fs::path g_tools_dir;  // run_cli_with_tools's argument

// The tools folder (report.py): $QDMETA_TOOLS_DIR; else share/qdmeta/tools beside the running
// executable's bin/ (an installed qdmeta); else the folder the program was built to use (the
// source tree's tools/, or the installed package's).
fs::path tools_dir() {
  if (const char* env = std::getenv("QDMETA_TOOLS_DIR")) return env;
  std::error_code ignored;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ignored);
  if (!exe.empty()) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "qdmeta" / "tools";
    if (fs::exists(installed / "report.py", ignored)) return installed;
  }
  return g_tools_dir;
}

// A tool script's own error, when it gave one: exit status 2 and a single stderr line
// "<script>: error: MESSAGE" (a damaged input, an output it may not write). Anything else (a
// traceback, a signal) is a fault of the script, shown as it is.
std::optional<std::string> script_error(const ProgramOutcome& r, const fs::path& script) {
  const std::string prefix = script.filename().string() + ": error: ";
  const std::string& e = r.error_output;
  if (r.status != kExitBadInput || !e.starts_with(prefix) || !e.ends_with('\n')) return std::nullopt;
  if (e.find('\n') != e.size() - 1) return std::nullopt;
  return e.substr(prefix.size(), e.size() - prefix.size() - 1);
}

// A tools/ script, e.g. ("report.py", "report script").
struct ToolScript {
  fs::path path;
  std::string label;
};

ToolScript tool_script(const std::string& name, const std::string& label) {
  const fs::path script = tools_dir() / name;
  if (!fs::exists(script)) throw InputError(fmt::format("{} {} not found (set QDMETA_TOOLS_DIR)", label, script.string()));
  return {script, label};
}

// A tools/ script ended while this program was being interrupted (Ctrl-C reaches the script too):
// the command ends as interrupted, not with the script's failure.
class ToolInterrupted : public Error {
 public:
  ToolInterrupted() : Error("interrupted") {}
};

// Runs a tools/ script with Debian's Python ($QDMETA_PYTHON overrides the interpreter) from an
// argument vector, never a shell: a path may hold any character. Its one-line error is ours.
void run_tool(const ToolScript& script, const std::vector<std::string>& args, const std::string& subject) {
  const char* env = std::getenv("QDMETA_PYTHON");
  std::vector<std::string> argv{env ? env : "/usr/bin/python3", script.path.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::fflush(stdout);  // our lines first, then the script's
  const ProgramOutcome r = run_program_capturing_stderr(argv, 64 * 1024);
  if (g_stop.load()) throw ToolInterrupted();  // its KeyboardInterrupt traceback is not news
  // The user sees one line for a damaged input: the script's, as ours.
  if (const std::optional<std::string> message = script_error(r, script.path)) throw InputError(*message);
  std::fputs(r.error_output.c_str(), stderr);  // warnings, or a traceback worth reading whole
  if (r.status != 0)
    throw Error(fmt::format("the {} {} failed (exit status {}) on {}", script.label, script.path.string(), r.status,
                            subject));
}

// Figures and report.md from the runs (or their summaries) under `dir`, written into `out`
// (default: `dir`), by tools/report.py with matplotlib.
int command_report(const std::string& dir, const std::optional<std::string>& out, bool quiet) {
  if (!fs::exists(fs::path(dir) / "experiment.toml"))
    throw InputError(fmt::format("{} holds no experiment (no experiment.toml): run qdmeta experiment first", dir));
  const ToolScript script = tool_script("report.py", "report script");
  std::vector<std::string> args{dir};
  if (out) args.insert(args.end(), {"--out", *out});  // the script makes the folder
  if (quiet) args.emplace_back("--quiet");
  run_tool(script, args, dir);
  return 0;
}

// `qdmeta report` on its own: Ctrl-C reaches the script too, and the command ends as experiment's
// does, in one line with status 130, not with the script's failure.
int command_report_alone(const std::string& dir, const std::optional<std::string>& out, bool quiet) {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    return command_report(dir, out, quiet);
  } catch (const ToolInterrupted&) {
    if (!quiet) fmt::print("interrupted: run the same command again to make the report\n");
    return kExitInterrupted;
  }
}

int command_experiment(const ExperimentArgs& a) {
  const ExperimentSpec spec = load_experiment(a.config, a.replicates, a.evals);
  ExperimentOptions options;
  if (a.seeds) options.replicates = parse_replicate_range(*a.seeds);
  if (a.conditions) options.conditions = parse_condition_list(*a.conditions);
  selected_conditions(spec, options.conditions);  // an unknown name is refused before anything is written
  options.restart_changed = a.restart_changed;
  if (a.plan) {
    if (a.summaries) options.summaries = *a.summaries;
    const PlannedRuns runs = write_experiment_plan(spec, a.out, options);
    if (!a.quiet)
      fmt::print("{} runs planned in {}{}: run line K with `qdmeta run --config CONFIG --seed SEED --out DIR` (or "
                 "scripts/slurm-experiment.sh), then this command without --plan runs the tests and the report\n",
                 runs.planned, (fs::path(a.out) / "plan.tsv").string(),
                 runs.summarised ? fmt::format(" ({} more are done: their summaries are in {})", runs.summarised,
                                               *a.summaries)
                                 : "");
    return 0;
  }
  if (a.summaries) {
    // Summaries need numpy only (tools/runs.py), not the report's matplotlib.
    const ToolScript script = tool_script("run_summary.py", "summary script");
    options.summaries = *a.summaries;
    options.summarise = [script](const fs::path& run_dir, const fs::path& file) {
      run_tool(script, {run_dir.string(), file.string()}, run_dir.string());
    };
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const bool tty = isatty(fileno(stdout)) != 0;
  std::string now;  // the part of the experiment this call runs, when not all of it
  if (a.seeds) now = "replicates " + *a.seeds;
  if (a.conditions) now += (now.empty() ? "" : " of ") + joined(options.conditions);
  if (!a.quiet)
    fmt::print("qdmeta {}: experiment '{}': {} conditions x {} replicates{}{} -> {}\n", kVersion, spec.name,
               spec.conditions.size(), spec.replicates, now.empty() ? std::string() : fmt::format(" (now {})", now),
               spec.evaluations ? fmt::format(", {} evaluations each", *spec.evaluations) : std::string(), a.out);
  std::fflush(stdout);  // before any error line in a log that holds both
  auto last = std::make_shared<double>(-1.0);
  auto last_line = std::make_shared<std::string>();
  auto last_decile = std::make_shared<int>(0);
  auto current = std::make_shared<ExperimentProgress>();  // where a failing task is named
  const ExperimentCallback progress = [&a, tty, last, last_line, last_decile, current](const ExperimentProgress& p) {
    *current = p;
    if (a.quiet) return;
    const double overall = (p.run - 1 + p.run_fraction) / p.runs;
    const std::string head = fmt::format("[{}/{}] {} seed {}: {}", p.run, p.runs, p.condition, p.replicate, p.phase);
    // Off a terminal (a log file, a batch job): a line per phase and per 10% of a run.
    const int decile = static_cast<int>(p.run_fraction * 10);
    const bool due = tty ? p.wall_seconds - *last >= 0.25 : head != *last_line || decile > *last_decile;
    if (!due) return;
    *last = p.wall_seconds;
    *last_line = head;
    *last_decile = decile;
    const double eta = overall > 0 ? p.wall_seconds * (1 - overall) / overall : 0;
    const std::string line = fmt::format("{} {:5.1f}%  overall {:5.1f}%  {:.0f} s elapsed, ETA {:.0f} s", head,
                                         100 * p.run_fraction, 100 * overall, p.wall_seconds, eta);
    if (tty) fmt::print("\r\033[K{}", line);
    else fmt::print("{}\n", line);
    std::fflush(stdout);
  };
  // Ctrl-C anywhere (a run, a test phase, the summary or report script) ends the command the same way.
  const auto interrupted = [&a] {
    if (!a.quiet) fmt::print("interrupted: run the same command again to continue\n");
    return kExitInterrupted;
  };
  // Not qdmeta's own: a task's code threw. Finished runs stand; this one resumes from its last checkpoint.
  const auto evaluation_failed = [&](const std::exception& e) {
    if (tty && !a.quiet) fmt::print("\n");
    std::fflush(stdout);
    fmt::print(stderr, "qdmeta: error: {}\n",
               one_line(fmt::format("evaluation failed in condition '{}' seed {} ({}): {}; the finished runs and this "
                                    "run's last checkpoint are kept: fix the task, then run the same command again "
                                    "to continue",
                                    current->condition, current->replicate, current->phase, e.what())));
    return kExitEvaluationFailed;
  };
  ExperimentResult r;
  try {
    r = run_experiment(spec, a.out, a.threads, progress, &g_stop, options);
  } catch (const ToolInterrupted&) {
    return interrupted();
  } catch (const TaskFailed& e) {
    return evaluation_failed(e);
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return evaluation_failed(e);
  }
  if (!a.quiet) {
    if (tty) fmt::print("\n");
    fmt::print("{} runs finished now, {} resumed, {} already finished; {} test phases\n", r.runs_done, r.runs_resumed,
               r.runs_skipped, r.tests_done);
    if (a.summaries)
      fmt::print("{} summaries written, {} runs skipped for the summary already in {}\n", r.summaries_written,
                 r.runs_kept, *a.summaries);
  }
  if (r.interrupted || g_stop.load()) return interrupted();
  if (a.no_report) return 0;
  try {
    command_report(a.out, std::nullopt, a.quiet);
  } catch (const ToolInterrupted&) {
    return interrupted();
  }
  if (!a.quiet) fmt::print("report: {}\n", (fs::path(a.out) / "report.md").string());
  return 0;
}

}  // namespace

int run_cli_with_tools(int argc, char** argv, const fs::path& tools, DistributionFactory make_distribution) {
  g_tools_dir = tools;
  // Past the file size limit (ulimit -f) a write then fails with EFBIG, which is reported in one
  // line with the directory left resumable, instead of SIGXFSZ killing the process mid-write.
  std::signal(SIGXFSZ, SIG_IGN);
  if (!has_notice_sink()) set_notice_sink(print_notice_to_stderr);  // a program's own sink stays
  ensure_core_plugins();  // as build_run() would, so that --help lists them in any program
  // Under mpirun every rank starts here; ranks > 0 serve rank 0 and never parse the command line.
  const std::unique_ptr<Distribution> distribution = make_distribution(argc, argv);
  if (const std::optional<int> status = distribution->serve_if_worker()) return *status;
  g_distribution = distribution.get();
  const int status = parse_and_run(argc, argv);
  g_distribution = nullptr;
  return status;
}

namespace {

// The top-level help's footer: what a config of this program may name, from the registries (a
// program that registers its own task or algorithm sees it listed here).
std::string describe_registered_parts() {
  std::string out = fmt::format("Registered in this program (what a config may name):\n  algorithm: {}\n",
                                joined(registered_algorithm_names()));
  for (const std::string& name : registered_task_names()) {
    const auto plugin = find_task_plugin(name);
    if (plugin == nullptr) continue;
    std::vector<std::string> kinds;
    for (const auto& [kind, reader] : plugin->meta_objectives) kinds.push_back(kind);
    const std::vector<std::string> tests = adaptation_test_names(*plugin);
    out += fmt::format("  [task] name = \"{}\": [meta_fitness] kind {}; adapt --test {}\n", name,
                       kinds.empty() ? "(none)" : joined(kinds), tests.empty() ? "(none)" : joined(tests));
  }
  if (const auto missing = unavailable_task_names(); !missing.empty())
    out += fmt::format("  not in this build: {}\n", joined(missing));
  out += fmt::format("  [mutation] kind: {}\n  [control] kind: {}\n  [archive] kind: {}\n  [feature_map] kind: {}\n",
                     joined(mutation_kinds()), joined(control_kinds()), joined(archive_kinds()),
                     joined(feature_map_kinds()));
  return out;
}

int parse_and_run(int argc, char** argv) {
  const int ranks = g_distribution->ranks();
  CLI::App app{"qdmeta: Quality-Diversity Meta-Evolution (QD-Meta), CVT-MAP-Elites and AURORA"};
  app.set_version_flag("--version", std::string(kVersion));
  app.footer(describe_registered_parts());
  app.require_subcommand(1);

  RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run one algorithm on one task to its evaluation budget");
  run_cmd->add_option("--config", run.config,
                      fmt::format("TOML config file (see configs/ and docs/config.md; algorithms: {}; tasks: {})",
                                  joined(registered_algorithm_names()), joined(registered_task_names())))
      ->required();
  run_cmd->add_option("--out", run.out, "Output directory for config.toml, metrics.csv, archive.csv")->required();
  run_cmd->add_option("--seed", run.seed, "Random seed (overrides the config's seed)");
  run_cmd->add_option("--evals", run.evals, "Evaluation budget (overrides budget.evaluations)")->check(CLI::PositiveNumber);
  run_cmd->add_option("--threads", run.threads, "Worker threads (0: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_flag("--overwrite", run.overwrite, "Replace a run already in --out");
  run_cmd->add_flag("--quiet", run.quiet, "Print nothing but errors");

  ResumeArgs resume;
  CLI::App* resume_cmd = app.add_subcommand("resume", "Continue an interrupted or killed run from its checkpoint");
  resume_cmd->add_option("--out", resume.out, "Directory of the run")->required();
  resume_cmd->add_option("--threads", resume.threads, "Worker threads (0: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  resume_cmd->add_flag("--quiet", resume.quiet, "Print nothing but errors");

  ExperimentArgs experiment;
  CLI::App* experiment_cmd =
      app.add_subcommand("experiment", "Every condition x replicate, the test phase on each archive, then the report");
  experiment_cmd->add_option("--config", experiment.config, "Experiment file (e.g. configs/rastrigin/experiment.toml)")
      ->required();
  experiment_cmd->add_option("--out", experiment.out, "Output directory: one folder per condition, one per seed")
      ->required();
  experiment_cmd->add_option("--replicates", experiment.replicates, "Replicates (seeds 1..R; overrides the file)")
      ->check(CLI::PositiveNumber);
  experiment_cmd->add_option("--seeds", experiment.seeds,
                             "Run only these replicates now, A-B or A (within 1..R; default: all)");
  experiment_cmd->add_option("--conditions", experiment.conditions,
                             "Run only these conditions now, by directory name: NAME,NAME,... (default: all)");
  experiment_cmd->add_option("--summaries", experiment.summaries,
                             "Keep each finished run's summary in DIR/<condition>/seed-<r>.json (with DIR/experiment.toml) "
                             "and skip the runs whose summary is there (tools/run_summary.py; needs numpy); with "
                             "--plan: check the summaries there, write DIR/experiment.toml and leave their runs out of the plan");
  experiment_cmd->add_option("--evals", experiment.evals, "Evaluation budget of every run (overrides the configs)")
      ->check(CLI::PositiveNumber);
  experiment_cmd->add_option("--threads", experiment.threads, "Worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
  experiment_cmd->add_flag("--quiet", experiment.quiet, "Print nothing but errors");
  experiment_cmd->add_flag("--no-report", experiment.no_report, "Skip the report at the end");
  experiment_cmd->add_flag("--restart-changed", experiment.restart_changed,
                           "Start over the runs (run directories, kept summaries) that an earlier call made with "
                           "another config than their condition has now (its file edited, its set or the budget "
                           "changed); without it they are refused, naming the keys that differ");
  experiment_cmd->add_flag("--plan", experiment.plan,
                           "Run nothing: write every condition's config and DIR/plan.tsv (one line per run) for a "
                           "batch system");

  std::string report_dir;
  std::optional<std::string> report_out;
  bool report_quiet = false;
  CLI::App* report_cmd = app.add_subcommand("report", "Figures (PNG) and report.md from an experiment's runs");
  report_cmd->add_option("dir", report_dir,
                         "Directory written by qdmeta experiment (its --out, or its --summaries: runs or their summaries)")
      ->required();
  report_cmd->add_option("--out", report_out, "Write report.md, figures/ and data/ here (default: DIR)");
  report_cmd->add_flag("--quiet", report_quiet, "Print nothing but errors");

  AdaptArgs adapt;
  CLI::App* adapt_cmd = app.add_subcommand("adapt", "Test phase: random search over a finished run's archive on unseen test functions");
  adapt_cmd->add_option("--run", adapt.run, "Directory of a finished run")->required();
  adapt_cmd->add_option("--test", adapt.test,
                        fmt::format("Test family by task ({}): writes adapt-NAME.csv; generalisation, where listed, "
                                    "scores the whole archive on the training and test families: writes "
                                    "generalisation.csv",
                                    describe_adaptation_tests()))
      ->required();
  adapt_cmd->add_option("--budget", adapt.budget,
                        "Evaluations per test function (default: the test family's, 100 on Rastrigin, 50 on RHex)")
      ->check(CLI::PositiveNumber);
  adapt_cmd->add_option("--solutions", adapt.solutions,
                        "Generalisation test: score this many archive solutions, drawn from the seed (default: all)")
      ->check(CLI::PositiveNumber);
  adapt_cmd->add_option("--seed", adapt.seed, "Seed of the search orders and test draws (default: the run's seed)");
  adapt_cmd->add_option("--threads", adapt.threads, "Worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
  adapt_cmd->add_flag("--quiet", adapt.quiet, "Print nothing but errors");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "qdmeta: {}\n", one_line(e.what()));
    return kExitBadInput;
  }

  if (ranks > 1 && !*run_cmd && !*resume_cmd)
    fmt::print(stderr, "qdmeta: warning: under MPI only run and resume use the other {} ranks; this command runs on rank 0\n",
               ranks - 1);
  try {
    if (*run_cmd) return command_run(run);
    if (*resume_cmd) return command_resume(resume);
    if (*adapt_cmd) return command_adapt(adapt);
    if (*experiment_cmd) return command_experiment(experiment);
    if (*report_cmd) return command_report_alone(report_dir, report_out, report_quiet);
  } catch (const TaskFailed& e) {  // in a command without a run to keep (adapt's tests)
    fmt::print(stderr, "qdmeta: error: {}\n", one_line(fmt::format("evaluation failed: {}", e.what())));
    return kExitEvaluationFailed;
  } catch (const std::bad_alloc&) {
    // The config's memory is estimated before a run starts; this is what the estimate missed.
    fmt::print(stderr, "qdmeta: error: out of memory (std::bad_alloc): the config asks for more memory than this "
                       "machine or its ulimit allows: lower its sizes (archive.bins, batch_size, database_capacity, "
                       "hidden, samples, ...)\n");
    return kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "qdmeta: error: {}\n", one_line(e.what()));  // whatever a value quoted in it holds
    return kExitBadInput;
  }
  return kExitBadInput;
}

}  // namespace

}  // namespace qdmeta
