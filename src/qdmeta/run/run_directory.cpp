#include "qdmeta/run/run_directory.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <sstream>

#include "qdmeta/assembly/config_fingerprint.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/rng.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/csv.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/run/run.hpp"

namespace fs = std::filesystem;

namespace qdmeta {
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

namespace {

// A run made with parts handed to build_run() names them in its config: rebuilt without them, a
// name is "not a valid choice" of the registry's; the message then says how to hand them again
// (the task's own message says so already).
BuiltRun build_for_resume(const RunState& state, const RunParts& parts) {
  try {
    return build_run(state.config(), state.config_path().string(), {}, parts);
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find("is not a valid choice") == std::string::npos || what.find("open_for_resume") != std::string::npos ||
        what.find("(the part handed over)") != std::string::npos)
      throw;
    throw InputError(fmt::format("{}; a part that the run in {} was made with, handed to build_run() as a value, is "
                                 "neither registered here nor handed over again: resume with the same parts, "
                                 "open_for_resume(dir, parts) (RunParts, qdmeta/assembly/run_parts.hpp), or register it",
                                 what, state.dir().string()));
  }
}

}  // namespace

ResumableRun open_for_resume(const RunState& state, const RunParts& parts) {
  const fs::path& dir = state.dir();
  if (!state.has_run()) throw InputError(fmt::format("{} holds no run (no config.toml)", dir.string()));
  // Refused as it stands: a refused resume changes nothing, a leftover checkpoint included.
  if (state.finished()) throw InputError(fmt::format("the run in {} has already finished: nothing to resume", dir.string()));
  ResumableRun r{build_for_resume(state, parts), {}};
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

}  // namespace qdmeta
