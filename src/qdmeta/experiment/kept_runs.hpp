#pragma once
// What earlier calls of an experiment left (run directories, kept summaries, plan.tsv's rows),
// checked against the experiment in force before a call changes anything. An experiment run
// again after one of its conditions changed (its config file edited, its `set` or the budget
// changed) must not pool runs made under the old config with runs made under the new one: each
// is compared with its condition by the resolved config fingerprint (config_fingerprint.hpp),
// and a mismatch is refused in one line naming the run and the keys that differ, unless the
// caller asked to start the changed runs over (--restart-changed): then they are listed for the
// experiment to make again.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "qdmeta/assembly/memory_estimate.hpp"
#include "qdmeta/experiment/experiment.hpp"

namespace qdmeta {

// A condition's config in force, resolved once per call: every key, the experiment's budget merged
// in, read by the config's readers without making its task, meta-objective or algorithm
// (BuildScope::kResolve).
struct ResolvedCondition {
  toml::table resolved;
  std::int64_t budget = 0;
  std::string fingerprint;
  MemoryEstimate memory;  // what a run of it would allocate (--plan refuses one over the limit)
};
std::vector<ResolvedCondition> resolve_conditions(const ExperimentSpec& spec);
// A config resolved as a condition is: at seed 1, with `evaluations` when given. Its fingerprint
// is the condition's, whatever seed a run of it has (a task may draw keys from the seed, as RHex's
// damage types), so `qdmeta run --seed S` of a planned run records what plan.tsv holds.
ResolvedCondition resolve_condition(const toml::table& config, const std::string& source,
                                    std::optional<std::int64_t> evaluations);

// The runs this call makes (its replicates and conditions), and whether it may start changed
// runs over.
struct RerunScope {
  ReplicateRange range;
  std::vector<const ExperimentCondition*> selected;
  bool restart_changed = false;
  bool covers(const ExperimentCondition& c, int replicate) const;
};

// Made under another config and to be made again: (condition index, replicate).
struct ChangedRuns {
  std::set<std::pair<std::size_t, int>> runs;       // run directories to start over
  std::set<std::pair<std::size_t, int>> summaries;  // kept summaries to make again
  bool run(std::size_t condition, int replicate) const { return runs.contains({condition, replicate}); }
  bool summary(std::size_t condition, int replicate) const { return summaries.contains({condition, replicate}); }
};

// The run directories OUT/<condition>/seed-<r> (every condition, replicates 1..R) that hold a
// run. A finished run of another budget is refused with the budget's own message unless the
// scope restarts it.
void check_run_directories(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                           const std::filesystem::path& out, const RerunScope& scope, ChangedRuns& changed);

// The summaries kept in `dir` by an earlier call: SUMMARIES/experiment.toml must have the same
// evaluations and tests, and each condition still in it the same config and set (the legacy rule,
// all that a summary without "config_fingerprint" is checked by, with its budget); a summary
// with a fingerprint must have its condition's.
void check_kept_summaries(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                          const std::filesystem::path& dir, const RerunScope& scope, ChangedRuns& changed);

// OUT/plan.tsv of an earlier --plan: each row's fingerprint (its last column; a plan written
// before fingerprints has none and is not checked) must be its condition's; the keys that differ
// are read from the condition.toml that plan wrote. Not checked when `replanning` with
// --restart-changed (the plan is written anew); a call that runs the experiment itself must not
// leave its batch tasks a plan of another config, so there --restart-changed does not excuse it.
void check_plan_rows(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                     const std::filesystem::path& out, const RerunScope& scope, bool replanning);

}  // namespace qdmeta
