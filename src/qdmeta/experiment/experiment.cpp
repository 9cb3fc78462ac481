#include "qdmeta/experiment/experiment.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <limits>
#include <set>
#include <sstream>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/assembly/memory_estimate.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/seconds_since.hpp"
#include "qdmeta/experiment/claim_rules.hpp"
#include "qdmeta/experiment/kept_runs.hpp"
#include "qdmeta/experiment/test_phase.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/io/run_lock.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/run/run.hpp"
#include "qdmeta/run/run_directory.hpp"

namespace fs = std::filesystem;

namespace qdmeta {

namespace {

std::string slug_of(std::string_view name) {
  std::string s;
  for (char c : name) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    const bool upper = c >= 'A' && c <= 'Z';
    if (keep || upper) s += upper ? static_cast<char>(c - 'A' + 'a') : c;
    else if (!s.empty() && s.back() != '-') s += '-';
  }
  while (!s.empty() && s.back() == '-') s.pop_back();
  return s;
}

}  // namespace

namespace {
void merge_into(toml::table& target, const toml::table& changes) {
  for (const auto& [k, v] : changes) {
    auto* sub = target[k].as_table();
    if (sub && v.is_table()) merge_into(*sub, *v.as_table());
    else target.insert_or_assign(k, v);
  }
}
}  // namespace

toml::table ExperimentCondition::effective_config() const {
  toml::table t = load_toml(config);
  if (set) merge_into(t, *set);
  return t;
}

fs::path replicate_dir(const fs::path& out, const ExperimentCondition& c, int replicate) {
  return out / c.slug / fmt::format("seed-{}", replicate);
}

fs::path summary_file(const fs::path& summaries, const ExperimentCondition& c, int replicate) {
  return summaries / c.slug / fmt::format("seed-{}.json", replicate);
}

ReplicateRange parse_replicate_range(std::string_view text) {
  const auto number = [](std::string_view s) -> std::optional<int> {
    int n = 0;
    const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), n);
    if (s.empty() || s.front() == '-' || error != std::errc() || end != s.data() + s.size() || n < 1) return std::nullopt;
    return n;
  };
  const std::size_t dash = text.find('-');
  const std::optional<int> first = number(text.substr(0, dash));
  const std::optional<int> last = dash == std::string_view::npos ? first : number(text.substr(dash + 1));
  if (!first || !last || *first > *last)
    throw InputError(fmt::format("replicates '{}' must be a range A-B or one replicate A, with 1 <= A <= B", text));
  return {*first, *last};
}

std::vector<std::string> parse_condition_list(std::string_view text) {
  std::vector<std::string> out;
  std::size_t from = 0;
  while (true) {
    const std::size_t comma = text.find(',', from);
    const std::string_view name = text.substr(from, comma == std::string_view::npos ? std::string_view::npos : comma - from);
    if (name.empty())
      throw InputError(fmt::format("conditions '{}' must be condition directory names separated by commas, e.g. "
                                   "cvt-map-elites,aurora",
                                   text));
    out.emplace_back(name);
    if (comma == std::string_view::npos) return out;
    from = comma + 1;
  }
}

std::vector<const ExperimentCondition*> selected_conditions(const ExperimentSpec& spec,
                                                            const std::vector<std::string>& slugs) {
  std::vector<const ExperimentCondition*> out;
  for (const std::string& slug : slugs)
    if (std::none_of(spec.conditions.begin(), spec.conditions.end(), [&](const auto& c) { return c.slug == slug; })) {
      std::vector<std::string_view> known;
      for (const auto& c : spec.conditions) known.push_back(c.slug);
      throw InputError(fmt::format("experiment '{}' has no condition '{}': its conditions are {}", spec.name, slug,
                                   fmt::join(known, ", ")));
    }
  for (const auto& c : spec.conditions)
    if (slugs.empty() || std::find(slugs.begin(), slugs.end(), c.slug) != slugs.end()) out.push_back(&c);
  return out;
}

ExperimentSpec load_experiment(const fs::path& file, std::optional<int> replicates,
                               std::optional<std::int64_t> evaluations) {
  const toml::table t = load_toml(file);
  const std::string where = file.string();
  toml::table resolved;  // an experiment file is read, not written back resolved
  ConfigReader root(t, where, resolved);
  ExperimentSpec spec;
  spec.name = root.string("name", file.stem().string());
  constexpr std::int64_t kMaxReplicates = 100'000;
  const auto file_replicates = static_cast<int>(root.integer("replicates", 1, 1, kMaxReplicates));
  spec.replicates = replicates.value_or(file_replicates);
  if (spec.replicates < 1 || spec.replicates > kMaxReplicates)
    throw InputError(fmt::format("{}: replicates = {} is out of range: must be in [1, {}]", where, spec.replicates,
                                 kMaxReplicates));
  constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
  spec.evaluations = root.optional_integer("evaluations", 1, kMax);
  if (evaluations) spec.evaluations = *evaluations;
  if (spec.evaluations && *spec.evaluations < 1)
    throw InputError(fmt::format("{}: evaluations = {} must be at least 1", where, *spec.evaluations));
  if (const auto n = root.optional_integer("generalisation_solutions", 1, kMax)) spec.generalisation_solutions = *n;
  spec.tests = root.strings("tests", {});
  const toml::array* claims = root.raw_tables("claim");  // checked below, once the conditions are known
  if (claims) spec.claims = *claims;
  const std::vector<ConfigReader> conditions = root.tables("condition");
  if (conditions.empty())
    throw InputError(fmt::format("{}: no [[condition]] tables: an experiment needs at least one", where));
  std::set<std::string> slugs;
  for (ConfigReader c : conditions) {
    ExperimentCondition cond;
    if (const toml::table* set = c.raw_table("set")) cond.set = *set;
    cond.name = c.string("name", "");
    const std::string config = c.string("config", "");
    if (cond.name.empty() || config.empty())
      throw InputError(fmt::format("{}: every [[condition]] needs a name and a config", where));
    cond.slug = slug_of(cond.name);
    if (cond.slug.empty() || !slugs.insert(cond.slug).second)
      throw InputError(fmt::format("{}: condition '{}' repeats another's name", where, cond.name));
    cond.config = fs::absolute(file.parent_path() / config);
    cond.config_name = config;
    if (!fs::exists(cond.config))
      throw InputError(fmt::format("{}: condition '{}' names a config that does not exist: {}", where, cond.name,
                                   cond.config.string()));
    spec.conditions.push_back(std::move(cond));
  }
  root.finish();
  // A malformed claim would fail only in the report, after every run: refuse it now.
  std::vector<std::string> names;
  for (const auto& c : spec.conditions) names.push_back(c.name);
  if (claims) check_claims(*claims, names, spec.tests, where);  // the file's nodes: a copy has no positions
  return spec;
}

namespace {

// The configs as absolute paths (a run directory's experiment.toml) or as the experiment file
// names them (a folder of summaries, committed and continued on other machines).
enum class ConfigPaths { kAbsolute, kAsWritten };

void write_spec(const ExperimentSpec& spec, const fs::path& out, ConfigPaths paths = ConfigPaths::kAbsolute) {
  toml::table t;
  t.insert("name", spec.name);
  t.insert("replicates", spec.replicates);
  if (spec.evaluations) t.insert("evaluations", *spec.evaluations);
  toml::array tests;
  for (const auto& s : spec.tests) tests.push_back(s);
  t.insert("tests", std::move(tests));
  if (spec.generalisation_solutions) t.insert("generalisation_solutions", static_cast<std::int64_t>(*spec.generalisation_solutions));
  toml::array conditions;
  for (const auto& c : spec.conditions) {
    toml::table entry{{"name", c.name}, {"slug", c.slug},
                      {"config", paths == ConfigPaths::kAbsolute ? c.config.string() : c.config_name}};
    if (c.set) entry.insert("set", *c.set);
    conditions.push_back(std::move(entry));
  }
  t.insert("condition", std::move(conditions));
  if (!spec.claims.empty()) t.insert("claim", spec.claims);
  std::ostringstream text;
  text << (paths == ConfigPaths::kAbsolute
               ? "# The experiment in force for the runs below (written by qdmeta experiment; read by qdmeta report).\n"
               : "# The experiment in force for the summaries below (written by qdmeta experiment --summaries; read "
                 "by qdmeta report).\n")
       << t << "\n";
  write_file_atomic(out / "experiment.toml", text.str());
}

ReplicateRange checked_range(const ExperimentSpec& spec, std::optional<ReplicateRange> range) {
  const ReplicateRange r = range.value_or(ReplicateRange{1, spec.replicates});
  if (r.first < 1 || r.last < r.first || r.last > spec.replicates)
    throw InputError(fmt::format("replicates {}-{} are not within the experiment's 1-{}: raise its replicates "
                                 "(--replicates)",
                                 r.first, r.last, spec.replicates));
  return r;
}

// The kept summaries checked (kept_runs.hpp), then SUMMARIES/experiment.toml written.
void keep_spec(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
               const fs::path& summaries, const RerunScope& scope, ChangedRuns& changed) {
  check_kept_summaries(spec, conditions, summaries, scope, changed);
  fs::create_directories(summaries);
  write_spec(spec, summaries, ConfigPaths::kAsWritten);
}

// Everything an earlier call left, checked against the conditions in force before anything changes.
ChangedRuns check_earlier_calls(const ExperimentSpec& spec, const std::vector<ResolvedCondition>& conditions,
                                const fs::path& out, const RerunScope& scope, bool planning) {
  ChangedRuns changed;
  check_run_directories(spec, conditions, out, scope, changed);
  check_plan_rows(spec, conditions, out, scope, planning);
  return changed;
}

// The runs of this call; refused before OUT is made when their files' paths would be too long.
RerunScope scope_of(const ExperimentSpec& spec, const fs::path& out, const ExperimentOptions& options) {
  RerunScope scope{checked_range(spec, options.replicates), selected_conditions(spec, options.conditions),
                   options.restart_changed};
  for (const ExperimentCondition* c : scope.selected)
    require_room_for_run_files(replicate_dir(out, *c, scope.range.last));  // the longest seed number
  return scope;
}

std::size_t index_of(const ExperimentSpec& spec, const ExperimentCondition& c) {
  return static_cast<std::size_t>(&c - spec.conditions.data());
}

}  // namespace

PlannedRuns write_experiment_plan(const ExperimentSpec& spec, const fs::path& out, const ExperimentOptions& options) {
  const RerunScope scope = scope_of(spec, out, options);
  const std::vector<ResolvedCondition> conditions = resolve_conditions(spec);
  const RunLock experiment_lock(out, RunLock::Mode::kExclusive, RunLock::Missing::kCreate);
  ChangedRuns changed = check_earlier_calls(spec, conditions, out, scope, /*planning=*/true);
  if (options.summaries) keep_spec(spec, conditions, *options.summaries, scope, changed);
  for (const auto& [i, r] : changed.runs) {  // its task then starts it anew (qdmeta run)
    const fs::path dir = replicate_dir(out, spec.conditions[i], r);
    const RunLock lock(dir, RunLock::Mode::kExclusive);
    clear_run_directory(dir);
  }
  write_spec(spec, out);
  for (const auto& c : spec.conditions) {
    toml::table config = c.effective_config();
    if (spec.evaluations) set_budget(config, *spec.evaluations);
    // A bad config was refused when its condition was resolved; a run too large for this machine
    // is refused now, not in a batch job.
    require_memory(conditions[index_of(spec, c)].memory, memory_limit(), c.config.string());
    fs::create_directories(out / c.slug);
    std::ostringstream text;
    text << "# " << c.name << ": " << c.config.string() << " as experiment '" << spec.name
         << "' runs it (written by qdmeta experiment --plan).\n"
         << config << "\n";
    write_file_atomic(out / c.slug / "condition.toml", text.str());
  }
  std::ostringstream plan;
  plan << "index\tcondition\tseed\tconfig\tdir\t" << kConfigFingerprintKey << "\n";
  PlannedRuns runs;
  for (int r = scope.range.first; r <= scope.range.last; ++r)  // replicate-major, as run_experiment
    for (const ExperimentCondition* condition : scope.selected) {
      const ExperimentCondition& c = *condition;
      const std::size_t i = index_of(spec, c);
      if (options.summaries && fs::is_regular_file(summary_file(*options.summaries, c, r)) && !changed.summary(i, r)) {
        ++runs.summarised;
        continue;
      }
      plan << ++runs.planned << '\t' << c.slug << '\t' << r << '\t' << (out / c.slug / "condition.toml").string()
           << '\t' << replicate_dir(out, c, r).string() << '\t' << conditions[i].fingerprint << '\n';
    }
  write_file_atomic(out / "plan.tsv", plan.str());
  return runs;
}

ExperimentResult run_experiment(const ExperimentSpec& spec, const fs::path& out, int threads,
                                const ExperimentCallback& progress, const std::atomic<bool>* stop,
                                const ExperimentOptions& options) {
  const RerunScope scope = scope_of(spec, out, options);
  const ReplicateRange range = scope.range;
  if (options.summaries && !options.summarise) throw Error("run_experiment: summaries asked for without a summariser");
  const std::vector<ResolvedCondition> conditions = resolve_conditions(spec);
  const RunLock experiment_lock(out, RunLock::Mode::kExclusive, RunLock::Missing::kCreate);  // one experiment per --out
  // Refuse before touching anything what earlier calls made under another config (or budget).
  ChangedRuns changed = check_earlier_calls(spec, conditions, out, scope, /*planning=*/false);
  if (options.summaries) keep_spec(spec, conditions, *options.summaries, scope, changed);
  write_spec(spec, out);
  const auto start = std::chrono::steady_clock::now();
  const auto wall = [&] { return seconds_since(start); };
  auto evaluator = make_evaluator(threads);
  ExperimentResult result;
  // Asked to stop: checked before each phase (a run checks it between its steps itself).
  const auto stopping = [&] { return stop != nullptr && stop->load() && (result.interrupted = true); };
  const int runs = static_cast<int>(scope.selected.size()) * (range.last - range.first + 1);
  int run = 0;
  for (int r = range.first; r <= range.last; ++r) {  // replicate-major: a partial experiment has every condition
    for (const ExperimentCondition* condition : scope.selected) {
      const ExperimentCondition& c = *condition;
      const std::size_t i = index_of(spec, c);
      ++run;
      if (stopping()) return result;
      ExperimentProgress p{run, runs, c.name, r, "run", 0.0, wall()};
      const std::optional<fs::path> summary =
          options.summaries ? std::optional(summary_file(*options.summaries, c, r)) : std::nullopt;
      if (summary && path_taken(*summary) && !changed.summary(i, r)) {  // kept: its directory may be on another machine
        p.phase = "kept";
        p.run_fraction = 1.0;
        if (progress) progress(p);
        ++result.runs_kept;
        continue;
      }
      const fs::path dir = replicate_dir(out, c, r);
      const RunLock lock(dir, RunLock::Mode::kExclusive, RunLock::Missing::kCreate);  // as `run` and `resume` do
      const auto report = [&](const RunProgress& rp) {
        p.run_fraction = std::min(1.0, static_cast<double>(rp.evals) / static_cast<double>(rp.budget));
        p.wall_seconds = wall();
        if (progress) progress(p);
      };
      const RunState state(dir);  // read under the lock, once
      std::optional<EliteTable> archive;  // what this call's run wrote to archive.csv, for its tests
      const bool restart = changed.run(i, r);  // made under another config: started over
      if (state.finished() && !restart) {
        remove_stray_checkpoint(state);
        p.phase = "skip";
        p.run_fraction = 1.0;
        if (progress) progress(p);
        ++result.runs_skipped;
      } else {
        RunResult rr;
        if (state.has_checkpoint() && !restart) {
          p.phase = "resume";
          ResumableRun resumable = open_for_resume(state);
          rr = run_to_budget(*resumable.built.algorithm, *evaluator, resumable.built.settings, dir, report, stop,
                             &resumable.cursor);
          if (rr.reason == StopReason::kBudget) archive = resumable.built.algorithm->elites();
          ++result.runs_resumed;
        } else {
          BuiltRun fresh = build_run(c.effective_config(), c.config.string(),
                                     {static_cast<std::uint64_t>(r), spec.evaluations});
          start_run_directory(dir, fresh, c.config.string(), threads, /*overwrite=*/true, conditions[i].fingerprint);
          rr = run_to_budget(*fresh.algorithm, *evaluator, fresh.settings, dir, report, stop);
          if (rr.reason == StopReason::kBudget) archive = fresh.algorithm->elites();
        }
        if (rr.reason == StopReason::kInterrupted) {
          result.interrupted = true;
          return result;
        }
        ++result.runs_done;
      }
      std::optional<RunState> ended;  // the state after this call's run, read once if a test needs it
      const auto finished = [&]() -> const RunState& {
        return state.finished() && !restart ? state : ended ? *ended : ended.emplace(dir);
      };
      for (const auto& test : spec.tests) {
        const bool generalisation = test == "generalisation";  // a table, not a curve
        if (fs::exists(dir / (generalisation ? std::string("generalisation.csv") : fmt::format("adapt-{}.csv", test))))
          continue;
        if (stopping()) return result;
        p.phase = "test " + test;
        p.wall_seconds = wall();
        if (progress) progress(p);
        const EliteTable* held = archive ? &*archive : nullptr;
        if (generalisation) generalise_run(finished(), std::nullopt, *evaluator, spec.generalisation_solutions, held);
        else adapt_run(finished(), test, std::nullopt, std::nullopt, *evaluator, held);
        ++result.tests_done;
      }
      if (summary) {
        if (stopping()) return result;
        p.phase = "summary";
        p.wall_seconds = wall();
        if (progress) progress(p);
        options.summarise(dir, *summary);
        ++result.summaries_written;
      }
    }
  }
  return result;
}

}  // namespace qdmeta
