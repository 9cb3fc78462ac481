#include "qdmeta/experiment/run_directory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/experiment/config_fingerprint.hpp"
#include "qdmeta/experiment/run.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/config.hpp"

namespace fs = std::filesystem;

namespace qdmeta {
namespace {
constexpr std::uint64_t kGeneralisationDraw = 0x6E4E;  // salt of the generalisation test's sample
}  // namespace

const std::vector<std::string>& run_files() {
  static const std::vector<std::string> files = {"config.toml", "metrics.csv", "archive.csv",
                                                 "summary.json", "meta.csv",   kCheckpointFile};
  return files;
}

void clear_run_directory(const fs::path& dir) {
  for (const auto& f : run_files()) fs::remove(dir / f);
  for (const auto& entry : fs::directory_iterator(dir))  // the old run's test-phase curves
    if (const auto name = entry.path().filename().string(); name.starts_with("adapt-") || name == "generalisation.csv")
      fs::remove(entry.path());
}

void start_run_directory(const fs::path& out, const BuiltRun& built, const std::string& config_file, int threads,
                         bool overwrite, const std::optional<std::string>& fingerprint) {
  bool holds_run = false;  // a dangling link counts: it is not followed but replaced
  for (const auto& f : run_files()) holds_run = holds_run || path_taken(out / f);
  if (holds_run && !overwrite)
    throw InputError(fmt::format("{} already holds a run: pass --overwrite to replace it, or continue it with "
                                 "qdmeta resume --out {}",
                                 out.string(), out.string()));
  if (holds_run) clear_run_directory(out);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(fmt::format("cannot create {}: {}", out.string(), ec.message()));

  toml::table written = built.resolved;
  toml::table provenance;
  provenance.insert("qdmeta_version", std::string(kVersion));
  provenance.insert("config_file", config_file);
  provenance.insert("threads", threads);
  provenance.insert(kConfigFingerprintKey,  // for the summariser
                    fingerprint.value_or(resolved_config_fingerprint(built.resolved)));
  written.insert_or_assign("provenance", std::move(provenance));
  std::ostringstream text;
  text << "# Resolved configuration of this run: every key in force, defaults included.\n" << written << "\n";
  write_file_atomic(out / "config.toml", text.str());
}

ResumableRun open_for_resume(const RunState& state, const RunParts& parts) {
  const fs::path& dir = state.dir();
  if (!state.has_run()) throw InputError(fmt::format("{} holds no run (no config.toml)", dir.string()));
  // Refused as it stands: a refused resume changes nothing, a leftover checkpoint included.
  if (state.finished()) throw InputError(fmt::format("the run in {} has already finished: nothing to resume", dir.string()));
  ResumableRun r{build_run(state.config(), state.config_path().string(), {}, parts), {}};
  if (!r.built.algorithm->checkpointable())
    throw InputError(fmt::format("algorithm '{}' cannot resume yet", r.built.settings.algorithm));
  r.cursor = read_checkpoint(dir, r.built.settings.fingerprint, *r.built.algorithm);
  // Everything is checked before anything changes: a refused resume leaves the directory as it was.
  CsvAppender::check_continuable(dir / "metrics.csv", metrics_columns(), r.cursor.metrics_bytes, r.cursor.metrics_hash);
  if (r.cursor.meta_bytes > 0)
    CsvAppender::check_continuable(dir / "meta.csv", meta_columns(), r.cursor.meta_bytes, r.cursor.meta_hash);
  fs::remove(dir / "summary.json");  // the run is unfinished again until it ends
  return r;
}

ResumableRun open_for_resume(const fs::path& dir, const RunParts& parts) {
  return open_for_resume(RunState(dir), parts);
}

bool remove_stray_checkpoint(const RunState& state) {
  // A run killed between writing its final summary and removing its checkpoint leaves both.
  if (!state.has_checkpoint() || !state.finished()) return false;
  fs::remove(state.dir() / kCheckpointFile);
  return true;
}

namespace {

// The config of the finished run in `state` and its seed; InputError when there is none, it has
// not finished, or config.toml is not a run's resolved config: one emptied or garbled would
// otherwise test the archive under defaults it never ran with (and seed 1).
struct FinishedRun {
  const toml::table& config;
  std::uint64_t seed;
};

FinishedRun finished_run(const RunState& state) {
  const fs::path& dir = state.dir();
  if (!state.has_run()) throw InputError(fmt::format("{} holds no run (no config.toml)", dir.string()));
  if (!state.finished())
    throw InputError(fmt::format("the run in {} has not finished: finish it (qdmeta resume --out {}) before testing it",
                                 dir.string(), dir.string()));
  const toml::table& config = state.config();
  const std::string path = state.config_path().string();
  if (!config["seed"].is_integer() || !config["algorithm"].is_string() || !config["provenance"].is_table())
    throw InputError(fmt::format("{} is not the resolved config of a run (it lacks seed, algorithm or [provenance]): "
                                 "it was emptied or damaged, so the run cannot be tested",
                                 path));
  const BuiltRun checked = build_run(config, path, {}, BuildScope::kTasksOnly);  // every key, as a run reads it
  return {config, checked.settings.seed};
}

}  // namespace

GeneralisationReport generalise_run(const RunState& state, std::optional<std::uint64_t> seed, Evaluator& evaluator,
                                    std::optional<Index> solutions, const EliteTable* archive) {
  if (solutions && *solutions < 1)
    throw InputError(fmt::format("generalisation: solutions = {} must be at least 1", *solutions));
  const fs::path& dir = state.dir();
  const FinishedRun run = finished_run(state);
  const toml::table& config = run.config;
  const std::uint64_t s = seed.value_or(run.seed);
  const auto groups = build_generalisation_groups(config, state.config_path().string(), s);
  std::optional<EliteTable> read;
  const EliteTable& elites = archive ? *archive : read.emplace(read_elites_csv(dir / "archive.csv", EliteValues::kRunArchive));
  GeneralisationReport r;
  r.archive_size = elites.size();
  RowMatrix scored = elites.solutions;
  if (solutions && *solutions < scored.rows()) {  // every group scores the same drawn solutions
    std::vector<Index> rows(static_cast<std::size_t>(scored.rows()));
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<Index>(i);
    Rng rng = Rng::stream(s, {key(StreamKey::kTest), kGeneralisationDraw});
    choose_without_replacement(rows, static_cast<std::size_t>(*solutions), rng);
    std::sort(rows.begin(), rows.end());  // archive order: the draw picks which, not the order
    RowMatrix drawn(*solutions, scored.cols());
    for (Index i = 0; i < *solutions; ++i) drawn.row(i) = scored.row(rows[static_cast<std::size_t>(i)]);
    scored = std::move(drawn);
  }
  for (const auto& g : groups) r.rows.push_back(whole_archive_mean(scored, *g, evaluator));
  r.file = dir / "generalisation.csv";
  write_generalisation_csv(r.file, r.rows);
  return r;
}

AdaptationReport adapt_run(const RunState& state, std::string_view test, std::optional<Index> budget,
                           std::optional<std::uint64_t> seed, Evaluator& evaluator, const EliteTable* archive) {
  const fs::path& dir = state.dir();
  const fs::path config_path = state.config_path();
  const FinishedRun run = finished_run(state);
  const toml::table& config = run.config;
  // Same default seed as the run: every condition of a replicate then meets the same tests.
  const std::uint64_t s = seed.value_or(run.seed);
  const auto tests = build_adaptation_tests(config, config_path.string(), test, s);
  std::optional<EliteTable> read;
  const EliteTable& elites = archive ? *archive : read.emplace(read_elites_csv(dir / "archive.csv", EliteValues::kRunArchive));
  AdaptationReport r;
  r.functions = tests->count();
  r.budget = budget ? *budget : tests->default_budget();
  r.archive_size = elites.size();
  r.curve = random_search_adaptation(elites.solutions, *tests, r.budget, s, evaluator);
  r.file = dir / fmt::format("adapt-{}.csv", test);
  write_adaptation_csv(r.file, r.curve);
  return r;
}

}  // namespace qdmeta
