#pragma once
// An experiment: conditions x replicates (seeds 1..R), each a run directory
// OUT/<condition>/seed-<r>, then the test phase on every archive. Re-running the same command
// skips finished runs, resumes those with a checkpoint and restarts the others, so a killed
// experiment continues where it was. A call may run a range of the replicates, and may keep a
// summary of each finished run in a folder of its own (a study committed run by run, continued
// on another machine from its summaries).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

struct ExperimentCondition {
  std::string name;               // as shown in the report, e.g. "QD-Meta Translation"
  std::string slug;               // its directory, e.g. "qd-meta-translation"
  std::filesystem::path config;   // the run config (absolute)
  std::string config_name;        // the run config as the experiment file names it (relative to the file)
  std::optional<toml::table> set; // keys replaced in that config (e.g. qd_meta.meta_population)
  // The config in force: the file with `set` merged in, table by table.
  toml::table effective_config() const;
};

struct ExperimentSpec {
  std::string name;
  int replicates = 1;
  std::optional<std::int64_t> evaluations;  // overrides every condition's budget
  std::vector<std::string> tests;           // test families run on every archive
  std::optional<Index> generalisation_solutions;  // score this many archive solutions (default: all)
  std::vector<ExperimentCondition> conditions;
  // The [[claim]] tables (what a paper says the conditions show), passed to the run's
  // experiment.toml for `qdmeta report`, which checks each (tools/report.py; docs/config.md).
  toml::array claims;
};

// Reads an experiment file (see configs/rastrigin/experiment.toml); condition configs are
// relative to it. The overrides replace the file's replicates and evaluations. InputError on
// an unknown key, a missing config, a duplicate condition.
ExperimentSpec load_experiment(const std::filesystem::path& file, std::optional<int> replicates,
                               std::optional<std::int64_t> evaluations);

// The replicates (seeds) first..last that one call runs.
struct ReplicateRange {
  int first = 1;
  int last = 1;
};

// "A-B" or "A" (qdmeta experiment --seeds), 1 <= A <= B; InputError otherwise.
ReplicateRange parse_replicate_range(std::string_view text);

// "a,b,..." (qdmeta experiment --conditions): condition directory names, e.g. "cvt-map-elites";
// InputError for an empty list or an empty name.
std::vector<std::string> parse_condition_list(std::string_view text);

// The conditions of `spec` that one call runs, in the experiment's order: those whose directory
// name (slug) is in `slugs`, or all of them when `slugs` is empty. InputError, listing the
// experiment's conditions, for a name it does not have.
std::vector<const ExperimentCondition*> selected_conditions(const ExperimentSpec& spec,
                                                            const std::vector<std::string>& slugs);

// Writes the summary of the finished run in `run_dir` into `summary_file` (the CLI: by
// tools/run_summary.py; README.md, "Experiments and the report").
using RunSummariser = std::function<void(const std::filesystem::path& run_dir, const std::filesystem::path& summary_file)>;

struct ExperimentOptions {
  std::optional<ReplicateRange> replicates;  // default: every replicate, 1..spec.replicates
  // The conditions to run now, by directory name (slug), e.g. the short ones of a study while a
  // session's last hour would not finish a long one; default (empty): every condition.
  std::vector<std::string> conditions;
  // Where each finished run's summary goes, SUMMARIES/<condition>/seed-<r>.json, once its test
  // phases are done, beside SUMMARIES/experiment.toml; a run whose summary is there is skipped
  // without its directory. Summaries made for another budget, config or tests are refused.
  std::optional<std::filesystem::path> summaries;
  RunSummariser summarise;  // required with summaries (not by write_experiment_plan)
  // What an earlier call made under another config than its condition has now (a run directory,
  // a kept summary, a plan.tsv row: kept_runs.hpp) is refused, naming the keys that differ; with
  // this, the changed runs of this call's replicates and conditions are started over instead
  // (--restart-changed).
  bool restart_changed = false;
};

// For a batch system (scripts/slurm-experiment.sh): writes DIR/experiment.toml, every condition's
// config in force (DIR/<slug>/condition.toml: its `set` merged in and the experiment's budget
// written into [budget]) and DIR/plan.tsv, one line per run in the order run_experiment() runs
// them: index (1-based), condition slug, seed, config, run directory, config_fingerprint (the
// condition's: config_fingerprint.hpp). `qdmeta run --config CONFIG --seed SEED --out DIR` then
// gives the bits run_experiment() would, which later skips the finished run. Only the runs of
// options.replicates and options.conditions; with options.summaries, those are checked and
// SUMMARIES/experiment.toml written as run_experiment() does, and a run whose summary is kept
// there is done and left out. What earlier calls left is checked as by run_experiment(); with
// options.restart_changed, a changed run's directory is emptied for its task to start it anew.
struct PlannedRuns {
  int planned = 0;     // lines of plan.tsv
  int summarised = 0;  // left out: their summaries are kept
};
PlannedRuns write_experiment_plan(const ExperimentSpec& spec, const std::filesystem::path& out,
                                  const ExperimentOptions& options = {});

// The summary of replicate `replicate` of condition `c` under `summaries`.
std::filesystem::path summary_file(const std::filesystem::path& summaries, const ExperimentCondition& c, int replicate);

struct ExperimentProgress {
  int run = 0;             // 1-based index of the current run
  int runs = 0;            // conditions x replicates of this call
  std::string condition;
  int replicate = 0;
  std::string phase;       // "run", "resume", "skip", "test ...", "summary", "kept"
  double run_fraction = 0; // of the current run's budget
  double wall_seconds = 0; // since the command started
};
using ExperimentCallback = std::function<void(const ExperimentProgress&)>;

struct ExperimentResult {
  bool interrupted = false;
  int runs_done = 0, runs_skipped = 0, runs_resumed = 0, tests_done = 0;
  int summaries_written = 0;
  int runs_kept = 0;  // skipped without their directory: their summary was already kept
};

// Runs the replicates and conditions of `options` (all by default), writes OUT/experiment.toml (the spec in
// force, read by the report) first. A range past spec.replicates is refused, and so is (before
// anything is written) what earlier calls left made under another config than the condition in
// force (a finished run of another budget among them), unless options.restart_changed.
ExperimentResult run_experiment(const ExperimentSpec& spec, const std::filesystem::path& out, int threads,
                                const ExperimentCallback& progress, const std::atomic<bool>* stop,
                                const ExperimentOptions& options = {});

// The run directory of one condition and replicate.
std::filesystem::path replicate_dir(const std::filesystem::path& out, const ExperimentCondition& c, int replicate);

}  // namespace qdmeta
