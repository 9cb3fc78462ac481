// The qdmeta command line: parse, build from the config, call the library. Every failure is
// one line on stderr and exit status 2.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/experiment/build.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/run.hpp"
#include "qdmeta/io/atomic_file.hpp"
#ifdef QDMETA_WITH_RHEX
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#endif

namespace fs = std::filesystem;
using namespace qdmeta;

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

constexpr int kExitBadInput = 2;
constexpr int kExitInterrupted = 130;

// Files whose presence means the directory already holds a run.
const char* const kRunFiles[] = {"config.toml", "metrics.csv", "archive.csv", "summary.json", "meta.csv"};

void prepare_out_dir(const fs::path& out, bool overwrite) {
  bool holds_run = false;
  for (const char* f : kRunFiles) holds_run = holds_run || fs::exists(out / f);
  if (holds_run && !overwrite)
    throw InputError(fmt::format("{} already holds a run: pass --overwrite to replace it", out.string()));
  if (holds_run)
    for (const char* f : kRunFiles) fs::remove(out / f);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw InputError(fmt::format("cannot create {}: {}", out.string(), ec.message()));
}

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
    std::string line = fmt::format("{:>5.1f}%  {} / {} evals  {} evals/s  elites {}  best {:.4g}  mean {:.4g}  ETA {:.0f} s",
                                   100 * fraction, p.evals, p.budget, human(rate), s.num_elites, s.obj_max, s.obj_mean, eta);
    if (tty) fmt::print("\r\033[K{}", line);
    else fmt::print("{}\n", line);
    std::fflush(stdout);
  };
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
  const fs::path out(a.out);
  prepare_out_dir(out, a.overwrite);

  toml::table written = built.resolved;
  toml::table provenance;
  provenance.insert("qdmeta_version", std::string(kVersion));
  provenance.insert("config_file", a.config);
  provenance.insert("threads", a.threads);
  written.insert_or_assign("provenance", std::move(provenance));
  std::ostringstream text;
  text << "# Resolved configuration of this run: every key in force, defaults included.\n" << written << "\n";
  write_file_atomic(out / "config.toml", text.str());

  auto evaluator = make_evaluator(a.threads);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const bool tty = isatty(fileno(stdout)) != 0;
  if (!a.quiet)
    fmt::print("qdmeta {}: {} on {} threads, seed {}, budget {} evaluations -> {}\n", kVersion, built.settings.algorithm,
               evaluator->workers(), built.settings.seed, built.settings.budget, out.string());
  const RunResult r = run_to_budget(*built.algorithm, *evaluator, built.settings, out, make_progress(a.quiet), &g_stop);
  if (!a.quiet) {
    if (tty) fmt::print("\n");
    fmt::print("{}: {} evaluations in {:.2f} s ({} evals/s); {} elites, coverage {:.4f}, best {:.6g}, mean {:.6g}, "
               "QD-score {:.6g}\nresults: {}\n",
               r.message, r.counters.total(), r.wall_seconds,
               human(r.wall_seconds > 0 ? static_cast<double>(r.counters.total()) / r.wall_seconds : 0),
               r.stats.num_elites, r.stats.coverage, r.stats.obj_max, r.stats.obj_mean, r.stats.qd_score, out.string());
  }
  return r.reason == StopReason::kInterrupted ? kExitInterrupted : 0;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef QDMETA_WITH_RHEX
  register_rhex_task();  // [task] name = "rhex"
#endif
  CLI::App app{"qdmeta: Quality-Diversity Meta-Evolution (QD-Meta), CVT-MAP-Elites and AURORA"};
  app.set_version_flag("--version", std::string(kVersion));
  app.require_subcommand(1);

  RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run one algorithm on one task to its evaluation budget");
  run_cmd->add_option("--config", run.config, "TOML config file (see configs/ and docs/config.md)")->required();
  run_cmd->add_option("--out", run.out, "Output directory for config.toml, metrics.csv, archive.csv")->required();
  run_cmd->add_option("--seed", run.seed, "Random seed (overrides the config's seed)");
  run_cmd->add_option("--evals", run.evals, "Evaluation budget (overrides budget.evaluations)")->check(CLI::PositiveNumber);
  run_cmd->add_option("--threads", run.threads, "Worker threads (0: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_flag("--overwrite", run.overwrite, "Replace a run already in --out");
  run_cmd->add_flag("--quiet", run.quiet, "Print nothing but errors");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "qdmeta: {}\n", e.what());
    return kExitBadInput;
  }

  try {
    if (*run_cmd) return command_run(run);
  } catch (const std::exception& e) {
    fmt::print(stderr, "qdmeta: error: {}\n", e.what());
    return kExitBadInput;
  }
  return kExitBadInput;
}
