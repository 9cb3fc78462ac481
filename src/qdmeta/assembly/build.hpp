#pragma once
// From a config file to a ready algorithm: reads the run's own keys and hands each other table
// to its reader (the task registry, standard_tables, the algorithm's builder), then refuses any
// key none of them took. docs/config.md lists the keys; keep the two in step.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/assembly/memory_estimate.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

enum class BudgetCount { kBottom, kAll };  // what the evaluation budget counts
inline constexpr EnumNames<BudgetCount, 2> kBudgetCountNames{{{BudgetCount::kBottom, "bottom"},
                                                              {BudgetCount::kAll, "all"}}};

struct RunSettings {
  std::string algorithm;
  std::string task;  // [task] name
  std::uint64_t seed = 1;
  std::int64_t budget = 0;  // evaluations; the run stops at the first generation at or past it
  BudgetCount counts = BudgetCount::kBottom;
  std::int64_t log_every = 0;  // evaluations between metrics rows
  double checkpoint_every = 600.0;  // seconds between checkpoints (0: after every generation)
  std::uint64_t fingerprint = 0;    // of the resolved config, stamped on checkpoints
  std::int64_t evals(const EvaluationCounters& c) const { return counts == BudgetCount::kAll ? c.total() : c.bottom; }
};

struct Overrides {
  std::optional<std::uint64_t> seed;
  std::optional<std::int64_t> evaluations;
};

struct BuiltRun {
  RunSettings settings;
  std::unique_ptr<Algorithm> algorithm;  // null when built with BuildScope::kTasksOnly
  toml::table resolved;  // every key in force, defaults included
  // Every task the algorithm hands to its evaluator, in a fixed order: the run's task, then
  // the meta-objective's (QD-Meta). The algorithm holds copies of these very instances (same
  // Task::id()), so an MPI evaluator can name a task by its place in this list.
  std::vector<Task> evaluation_tasks;
  // What the run will allocate, estimated from the config (checked against the machine's limit
  // before the algorithm is built).
  MemoryEstimate memory;
};

// The evaluation budget, [budget] evaluations: every reader and writer of the key outside
// build_run (which reads it with its default and range) goes through these two.
void set_budget(toml::table& config, std::int64_t evaluations);  // makes [budget] where missing
// The budget `config` names (a run's resolved config.toml names it); nullopt when it names none.
std::optional<std::int64_t> configured_budget(const toml::table& config);

// kTasksOnly reads and checks the whole config but builds no algorithm: what an MPI worker
// needs (the evaluation tasks) without the algorithm's memory (e.g. QD-Meta's database).
// kResolve reads and checks the whole config and makes nothing: the resolved config, settings
// (the budget), fingerprint and memory estimate, with the task only its shape where its plugin
// reads one (TaskPlugin::read_shape) and no meta-objective (ConfigReader::resolving()); what an
// experiment needs of each condition and kept run. Its evaluation_tasks evaluate nothing.
enum class BuildScope { kRun, kTasksOnly, kResolve };

// Throws InputError naming the file and key for anything wrong in the config.
BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides = {},
                   BuildScope scope = BuildScope::kRun);
// The same, with `parts` used in place of the registered ones the config would name (run_parts.hpp).
BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides,
                   const RunParts& parts, BuildScope scope = BuildScope::kRun);

// The unseen test functions named `test` for the task of a run's config (`qdmeta adapt`):
// Rastrigin "dimension" (120 distinct pairs drawn from `seed`) or "translation" (the 120-point
// grid); a registered task's families (task_registry.hpp; RHex: damage, obstacle,
// damage-training, obstacle-training). An unknown name lists the valid ones.
std::unique_ptr<AdaptationTests> build_adaptation_tests(const toml::table& config, const std::string& source,
                                                        std::string_view test, std::uint64_t seed);

// The groups of the generalisation test (`qdmeta adapt --test generalisation`): the task's
// generalisation families in report order. InputError for a task without one.
std::vector<std::unique_ptr<AdaptationTests>> build_generalisation_groups(const toml::table& config,
                                                                         const std::string& source, std::uint64_t seed);

}  // namespace qdmeta
