#include "qdmeta/assembly/build.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <string_view>

#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/assembly/run_parts.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/registry.hpp"
#include "qdmeta/plugin/task_registry.hpp"

namespace qdmeta {
namespace {

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int64_t>::max();
constexpr std::string_view kBudgetTable = "budget", kBudgetKey = "evaluations";

// [task] through the part handed over, else through the registered task it names.
Task read_task(ConfigReader& task_table, const RunParts& parts) {
  if (parts.task && parts.task_reader)
    throw InputError(fmt::format("{}: RunParts holds a task and a task_reader: give one of them", task_table.source()));
  if (parts.task) {
    read_part_name(task_table, "name", parts.task->name());
    return *parts.task;
  }
  if (!parts.task_reader) return read_registered_task(task_table);
  const TaskPart& part = *parts.task_reader;
  read_part_name(task_table, "name", part.name);
  Task task = part.read(task_table);
  if (task.name() != part.name)
    throw InputError(fmt::format("{}: the task part \"{}\" made a task named '{}': they must be the same name",
                                 task_table.source(), part.name, task.name()));
  return task;
}

// A part handed over that the run's algorithm never read (an archive handed to qd-meta): refused,
// not ignored. A part that was read recorded its name in the resolved config.
void refuse_unread_parts(const RunParts& parts, const toml::table& resolved, const std::string& source,
                         const std::string& algorithm) {
  const struct {
    const char* table;
    const char* what;
    const std::string* kind;
  } given[] = {{"control", "controller", parts.controller ? &parts.controller->kind : nullptr},
               {"feature_map", "feature-map", parts.feature_map ? &parts.feature_map->kind : nullptr},
               {"archive", "archive", parts.archive ? &parts.archive->kind : nullptr}};
  for (const auto& g : given) {
    if (g.kind == nullptr) continue;
    const auto* kind = resolved[g.table]["kind"].as_string();
    if (kind == nullptr || kind->get() != *g.kind)
      throw InputError(fmt::format("{}: the {} part \"{}\" was handed over, but algorithm '{}' does not read [{}] "
                                   "kind \"{}\": leave the part out, or choose an algorithm that takes it",
                                   source, g.what, *g.kind, algorithm, g.table, *g.kind));
  }
}

}  // namespace

void set_budget(toml::table& config, std::int64_t evaluations) {
  // A [budget] that is not a table stays as it is, for build_run to refuse naming it.
  if (!config.contains(kBudgetTable)) config.insert(kBudgetTable, toml::table{});
  if (auto* budget = config[kBudgetTable].as_table()) budget->insert_or_assign(kBudgetKey, evaluations);
}

std::optional<std::int64_t> configured_budget(const toml::table& config) {
  return config[kBudgetTable][kBudgetKey].value<std::int64_t>();
}

BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides,
                   BuildScope scope) {
  return build_run(config, source, overrides, RunParts{}, scope);
}

BuiltRun build_run(const toml::table& config, const std::string& source, const Overrides& overrides,
                   const RunParts& parts, BuildScope scope) {
  ensure_core_plugins();
  toml::table effective = config;
  // A run's own config.toml carries a [provenance] table; it describes, it does not configure,
  // so a resolved config can be run again as it is.
  effective.erase("provenance");
  if (overrides.seed) effective.insert_or_assign("seed", static_cast<std::int64_t>(*overrides.seed));
  if (overrides.evaluations) set_budget(effective, *overrides.evaluations);

  BuiltRun built;
  ConfigReader root(effective, source, built.resolved);
  root.set_resolving(scope == BuildScope::kResolve);
  RunSettings& s = built.settings;
  std::shared_ptr<const AlgorithmBuilder> registered;  // keeps a registered builder alive
  const AlgorithmBuilder* builder = nullptr;
  if (parts.algorithm) {
    s.algorithm = read_part_name(root, "algorithm", parts.algorithm->name);
    builder = &parts.algorithm->build;
  } else {
    const std::vector<std::string> algorithms = registered_algorithm_names();
    if (algorithms.empty()) throw InputError(fmt::format("{}: no algorithm is registered", source));
    const std::string valid_algorithms = quoted_names(algorithms);
    const bool has_default = std::find(algorithms.begin(), algorithms.end(), "map-elites") != algorithms.end();
    s.algorithm = root.string("algorithm", has_default ? "map-elites" : algorithms.front(), valid_algorithms);
    registered = find_algorithm(s.algorithm);
    if (registered == nullptr) root.not_a_valid_choice("algorithm", s.algorithm, valid_algorithms);
    builder = registered.get();
  }
  s.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0, kMaxInt));

  ConfigReader budget = root.table(kBudgetTable);
  s.budget = budget.integer(kBudgetKey, 1'000'000, 1, kMaxInt);
  s.counts = budget.choice("counts", BudgetCount::kBottom, kBudgetCountNames);
  ConfigReader log = root.table("log");
  s.log_every = log.integer("every", 0, 0, kMaxInt);
  if (s.log_every == 0) s.log_every = std::max<std::int64_t>(1, s.budget / 200);
  ConfigReader checkpoint = root.table("checkpoint");
  s.checkpoint_every = checkpoint.number("every_seconds", s.checkpoint_every, 0.0, 1e9);

  ConfigReader task_table = root.table("task");
  Task task = read_task(task_table, parts);
  s.task = task.name();
  ConfigReader mutation_table = root.table("mutation");
  MutationParams mutation;
  if (parts.variation) {
    read_part_name(mutation_table, "kind", parts.variation->kind);
    mutation.variation = parts.variation->read(mutation_table, task);  // its key errors name the file already
    if (!mutation.variation) throw InputError(fmt::format("{}: the variation part made no operator", source));
    mutation.variation_name = parts.variation->kind;
  } else {
    mutation = read_mutation_table(mutation_table, task);
  }
  built.evaluation_tasks.push_back(task);

  // The builder protocol (algorithm_registry.hpp), the same around every builder: read and
  // estimate, every key checked, the memory estimate checked, and only then anything allocated.
  AlgorithmBuild b{root, std::move(task), mutation, s, built, parts};
  AlgorithmMaker make = (*builder)(b);
  root.finish();  // every table opened, the builder's included, whether or not it finished them
  refuse_unread_parts(parts, built.resolved, source, s.algorithm);
  if (scope == BuildScope::kRun) {
    require_memory(built.memory, memory_limit(), source);
    if (!make) throw Error(fmt::format("{}: the builder of algorithm '{}' returned no maker", source, s.algorithm));
    built.algorithm = make();
  }
  s.fingerprint = config_fingerprint(built.resolved);
  return built;
}

namespace {

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += fmt::format("{}{}", out.empty() ? "" : ", ", n);
  return out.empty() ? "none" : out;
}

}  // namespace

std::unique_ptr<AdaptationTests> build_adaptation_tests(const toml::table& config, const std::string& source,
                                                        std::string_view test, std::uint64_t seed) {
  ensure_core_plugins();
  toml::table resolved;
  ConfigReader root(config, source, resolved);
  ConfigReader task_table = root.table("task");
  const Task task = read_registered_task(task_table);
  const auto plugin = find_task_plugin(task.name());
  const auto& names = plugin->adaptation_tests;
  if (!plugin->read_adaptation_tests || names.empty())
    throw InputError(fmt::format("task '{}' has no test phase", task.name()));
  if (std::find(names.begin(), names.end(), test) == names.end())
    throw InputError(fmt::format("unknown test '{}' for task '{}': valid tests are {}{}", test, task.name(), listed(names),
                                 plugin->generalisation_groups.empty() ? "" : ", generalisation"));
  return plugin->read_adaptation_tests(config, source, task, test, seed);
}

std::vector<std::unique_ptr<AdaptationTests>> build_generalisation_groups(const toml::table& config,
                                                                         const std::string& source, std::uint64_t seed) {
  ensure_core_plugins();
  toml::table resolved;
  ConfigReader root(config, source, resolved);
  ConfigReader task_table = root.table("task");
  const Task task = read_registered_task(task_table);
  const auto plugin = find_task_plugin(task.name());
  if (plugin->generalisation_groups.empty())
    throw InputError(fmt::format("task '{}' has no generalisation test: valid tests are {}", task.name(),
                                 listed(plugin->adaptation_tests)));
  std::vector<std::unique_ptr<AdaptationTests>> groups;
  for (const auto& name : plugin->generalisation_groups)
    groups.push_back(plugin->read_adaptation_tests(config, source, task, name, seed));
  return groups;
}

}  // namespace qdmeta
