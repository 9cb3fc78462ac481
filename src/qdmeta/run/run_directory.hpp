#pragma once
// A run directory's life: started (config.toml with provenance), resumed from its checkpoint,
// or recognised as finished. Shared by `qdmeta run`, `qdmeta resume` and `qdmeta experiment`.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/run/checkpoint.hpp"
#include "qdmeta/run/run_state.hpp"

namespace qdmeta {

// Files whose presence means a directory holds a run.
const std::vector<std::string>& run_files();

// Removes the run in `dir`: its files and its test phases' (the caller holds its lock).
void clear_run_directory(const std::filesystem::path& dir);

// Makes `out` ready for a new run: refuses (InputError) a directory that holds one unless
// `overwrite`, in which case the old run's files go. Then writes config.toml: the resolved
// config plus a [provenance] table (program version, config file, threads, config_fingerprint:
// assembly/config_fingerprint.hpp). `fingerprint`: an experiment's run carries its condition's
// (the condition resolved with seed 1, so that values drawn from the seed, e.g. RHex's
// meta_fitness.damage_types, do not tell its replicates apart); by default the run's own.
void start_run_directory(const std::filesystem::path& out, const BuiltRun& built, const std::string& config_file,
                         int threads, bool overwrite, const std::optional<std::string>& fingerprint = std::nullopt);

struct ResumableRun {
  BuiltRun built;
  RunCursor cursor;
};

// Rebuilds the run in `state` from its config.toml (with `parts`, those it was made with, handed
// over again) and loads its checkpoint. InputError when the run has finished, cannot checkpoint,
// or its checkpoint is missing, damaged or mismatched.
ResumableRun open_for_resume(const RunState& state, const RunParts& parts = {});
ResumableRun open_for_resume(const std::filesystem::path& dir, const RunParts& parts = {});

// A finished run (summary.json says it reached its budget) that still has a checkpoint was
// killed between the two last steps of its end: removes the stale checkpoint and returns true.
bool remove_stray_checkpoint(const RunState& state);

}  // namespace qdmeta
