#include "qdmeta/experiment/test_phase.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/io/csv.hpp"

namespace fs = std::filesystem;

namespace qdmeta {
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
  const BuiltRun checked = build_run(config, path, {}, BuildScope::kResolve);  // every key, as a run reads it
  return {config, checked.settings.seed};
}

constexpr std::uint64_t kGeneralisationDraw = 0x6E4E;  // salt of the generalisation test's sample

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
