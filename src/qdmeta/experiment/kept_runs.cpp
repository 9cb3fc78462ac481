#include "qdmeta/experiment/kept_runs.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <optional>
#include <sstream>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/run/run_state.hpp"
#include "qdmeta/run/summary.hpp"

namespace fs = std::filesystem;

namespace qdmeta {
namespace {

std::string evaluations_text(std::optional<std::int64_t> evaluations) {
  return evaluations ? fmt::format("evaluations = {}", *evaluations) : "each condition's own budget";
}

std::vector<std::string> strings_of(const toml::node_view<const toml::node>& array) {
  std::vector<std::string> out;
  if (const auto* a = array.as_array())
    for (const auto& v : *a) out.push_back(v.value_or<std::string>(""));
  return out;
}

// The keys of a summary's "config" (the few the report reads: tools/runs.py config_keys) whose
// values the condition in force does not have.
std::vector<std::string> summary_keys_differing(const nlohmann::json& config, const toml::table& resolved) {
  std::vector<std::string> out;
  if (!config.is_object()) return out;
  for (const auto& [key, value] : config.items()) {
    if (value.is_string() && resolved[key].value<std::string>() != value.get<std::string>()) out.push_back(key);
    if (!value.is_object()) continue;
    for (const auto& [inner, v] : value.items())
      if (v.is_string() && resolved[key][inner].value<std::string>() != v.get<std::string>())
        out.push_back(key + "." + inner);
  }
  return out;
}

std::vector<std::string> split(std::string_view line, char separator) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (std::size_t at = line.find(separator); at != std::string_view::npos; at = line.find(separator, from)) {
    out.emplace_back(line.substr(from, at - from));
    from = at + 1;
  }
  out.emplace_back(line.substr(from));
  return out;
}

// Advice for a changed run that --restart-changed would not start over in this call.
std::string restart_advice(const RerunScope& scope) {
  return scope.restart_changed ? "start it over with --restart-changed and replicates and conditions that include it "
                                 "(--seeds, --conditions)"
                               : "start the changed runs over with --restart-changed";
}

}  // namespace

bool RerunScope::covers(const ExperimentCondition& c, int replicate) const {
  return replicate >= range.first && replicate <= range.last &&
         std::find(selected.begin(), selected.end(), &c) != selected.end();
}

ResolvedCondition resolve_condition(const toml::table& config, const std::string& source,
                                    std::optional<std::int64_t> evaluations) {
  BuiltRun built = build_run(config, source, {1, evaluations}, BuildScope::kResolve);
  ResolvedCondition r{std::move(built.resolved), built.settings.budget, "", std::move(built.memory)};
  r.fingerprint = resolved_config_fingerprint(r.resolved);
  return r;
}

std::vector<ResolvedCondition> resolve_conditions(const ExperimentSpec& spec) {
  std::vector<ResolvedCondition> out;
  for (const auto& c : spec.conditions)
    out.push_back(resolve_condition(c.effective_config(), c.config.string(), spec.evaluations));
  return out;
}

void check_run_directories(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                           const fs::path& out, const RerunScope& scope, ChangedRuns& changed) {
  for (std::size_t i = 0; i < spec.conditions.size(); ++i) {
    const ExperimentCondition& c = spec.conditions[i];
    for (int r = 1; r <= spec.replicates; ++r) {
      const RunState state(replicate_dir(out, c, r));
      if (!state.has_run()) continue;
      // The fingerprint the run was started with (its condition's, seed-independent); a run made
      // before fingerprints is resolved again and compared with the condition at its own seed,
      // whose seed-drawn values (RHex's meta_fitness.damage_types) its config.toml holds.
      // The run's config is resolved (so checked) whatever its fingerprint; the condition at the
      // run's seed only for a run that is not plainly its condition's. Each once.
      const toml::table run =
          build_run(state.config(), state.config_path().string(), {}, BuildScope::kResolve).resolved;
      const std::optional<std::string> stored =
          state.config()["provenance"][kConfigFingerprintKey].value<std::string>();
      if (stored && *stored == conditions[i].fingerprint) continue;
      const toml::table condition_at_seed =
          build_run(c.effective_config(), c.config.string(), {static_cast<std::uint64_t>(r), spec.evaluations},
                    BuildScope::kResolve)
              .resolved;
      if (!stored && resolved_config_fingerprint(run) == resolved_config_fingerprint(condition_at_seed)) continue;
      if (scope.restart_changed && scope.covers(c, r)) {
        changed.runs.insert({i, r});
        continue;
      }
      if (state.finished() && state.budget() != conditions[i].budget)
        throw InputError(fmt::format("{} finished with a budget of {} evaluations but this experiment asks for {}: "
                                     "use another --out or the same --evals",
                                     state.dir().string(), state.budget(), conditions[i].budget));
      throw InputError(fmt::format("{} was run with another config than condition '{}' has now ({}): {}, or "
                                   "use another --out",
                                   state.dir().string(), c.name, keys_that_differ(differing_keys(run, condition_at_seed)),
                                   restart_advice(scope)));
    }
  }
}

void check_kept_summaries(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                          const fs::path& dir, const RerunScope& scope, ChangedRuns& changed) {
  const fs::path file = dir / "experiment.toml";
  const std::string advice = "use another --summaries folder, or the experiment that made them";
  std::vector<bool> condition_changed(spec.conditions.size(), false);  // its config or set (the legacy rule)
  if (path_taken(file)) {
    const toml::table kept = load_toml(file);
    const std::optional<std::int64_t> evaluations = kept["evaluations"].value<std::int64_t>();
    if (evaluations != spec.evaluations)
      throw InputError(fmt::format("{}: its summaries were made with {}, this experiment has {}: {}", file.string(),
                                   evaluations_text(evaluations), evaluations_text(spec.evaluations), advice));
    if (strings_of(kept["tests"]) != spec.tests)
      throw InputError(fmt::format("{}: its summaries were made with other tests than this experiment's: {}",
                                   file.string(), advice));
    if (const auto* kept_conditions = kept["condition"].as_array()) {
      for (const auto& node : *kept_conditions) {
        const auto* k = node.as_table();
        if (!k) continue;
        const std::string slug = (*k)["slug"].value_or<std::string>("");
        for (std::size_t i = 0; i < spec.conditions.size(); ++i) {
          const ExperimentCondition& c = spec.conditions[i];
          if (c.slug != slug) continue;
          const toml::table kept_set = (*k)["set"].as_table() ? *(*k)["set"].as_table() : toml::table{};
          if ((*k)["config"].value_or<std::string>("") == c.config_name && kept_set == c.set.value_or(toml::table{}))
            continue;
          if (scope.restart_changed) {  // its summaries are made again, each one below
            condition_changed[i] = true;
            continue;
          }
          throw InputError(fmt::format("{}: condition '{}' was run with config {} and another set than this "
                                       "experiment's (config {}): make its summaries again with --restart-changed, or {}",
                                       file.string(), c.name, (*k)["config"].value_or<std::string>("?"),
                                       c.config_name, advice));
        }
      }
    }
  }
  for (int r = 1; r <= spec.replicates; ++r) {
    for (std::size_t i = 0; i < spec.conditions.size(); ++i) {
      const ExperimentCondition& c = spec.conditions[i];
      const fs::path summary = summary_file(dir, c, r);
      if (!path_taken(summary)) continue;
      nlohmann::json kept;
      try {
        kept = nlohmann::json::parse(read_regular_file(summary, kMaxTextFileBytes));
      } catch (const nlohmann::json::exception& e) {
        throw InputError(fmt::format("{} is unreadable: {}", summary.string(), e.what()));
      }
      // Its "summary" is the run's summary.json (tools/runs.py), read as that file is.
      const nlohmann::json* run_summary = kept.is_object() && kept.contains("summary") ? &kept["summary"] : nullptr;
      if (run_summary == nullptr) throw InputError(fmt::format("{} is unreadable: it holds no summary", summary.string()));
      const std::optional<std::int64_t> kept_budget = parse_summary(run_summary->dump(), summary.string()).integer("budget");
      if (!kept_budget)
        throw InputError(fmt::format("{} is unreadable: its summary has no whole-number budget", summary.string()));
      const std::int64_t budget = *kept_budget;
      std::optional<std::string> fingerprint;
      if (kept.contains(kConfigFingerprintKey)) {
        const nlohmann::json& f = kept[kConfigFingerprintKey];
        if (!f.is_string() || !is_config_fingerprint(f.get<std::string>()))
          throw InputError(fmt::format("{}: {} must be 16 lowercase hex digits", summary.string(), kConfigFingerprintKey));
        fingerprint = f.get<std::string>();
      }
      const bool same = !condition_changed[i] && budget == conditions[i].budget &&
                        (!fingerprint || *fingerprint == conditions[i].fingerprint);
      if (same) continue;
      if (scope.restart_changed && scope.covers(c, r)) {
        changed.summaries.insert({i, r});
        continue;
      }
      if (budget != conditions[i].budget && !scope.restart_changed)
        throw InputError(fmt::format("{} was made with a budget of {} evaluations but this experiment asks for {}: {}",
                                     summary.string(), budget, conditions[i].budget, advice));
      std::string differing;
      if (fingerprint && *fingerprint != conditions[i].fingerprint) {
        const auto keys = summary_keys_differing(kept.value("config", nlohmann::json::object()), conditions[i].resolved);
        differing = keys.empty() ? " (which keys differ, its summary does not keep)" : fmt::format(" ({})", keys_that_differ(keys));
      }
      throw InputError(fmt::format("{} was made with another config than condition '{}' has now{}: {}, or {}",
                                   summary.string(), c.name, differing, restart_advice(scope), advice));
    }
  }
}

void check_plan_rows(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                     const fs::path& out, const RerunScope& scope, bool replanning) {
  const fs::path plan = out / "plan.tsv";
  if (!path_taken(plan) || (replanning && scope.restart_changed)) return;
  std::istringstream lines(read_regular_file(plan, kMaxTextFileBytes));
  std::string line;
  std::getline(lines, line);
  const std::vector<std::string> header = split(line, '\t');
  const auto column = [&](std::string_view name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t slug_at = column("condition"), seed_at = column("seed"), fingerprint_at = column(kConfigFingerprintKey);
  if (fingerprint_at == header.size() || slug_at == header.size() || seed_at == header.size()) return;  // before fingerprints
  for (int row = 1; std::getline(lines, line); ++row) {
    const std::vector<std::string> cells = split(line, '\t');
    if (cells.size() != header.size()) continue;
    for (std::size_t i = 0; i < spec.conditions.size(); ++i) {
      const ExperimentCondition& c = spec.conditions[i];
      if (c.slug != cells[slug_at] || cells[fingerprint_at] == conditions[i].fingerprint) continue;
      std::string differing;  // from the condition.toml the plan wrote, when it is still readable
      try {
        const fs::path planned = out / c.slug / "condition.toml";
        const toml::table old = build_run(load_toml(planned), planned.string(), {}, BuildScope::kResolve).resolved;
        differing = fmt::format(" ({})", keys_that_differ(differing_keys(old, conditions[i].resolved)));
      } catch (const Error&) {
      }
      throw InputError(fmt::format("{}: row {} ({} seed {}) was planned with another config than condition '{}' has "
                                   "now{}: plan again with --restart-changed, or use another --out",
                                   plan.string(), row, c.slug, cells[seed_at], c.name, differing));
    }
  }
}

}  // namespace qdmeta
