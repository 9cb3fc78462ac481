#pragma once
// A run directory's life: started (config.toml with provenance), resumed from its checkpoint,
// or recognised as finished. Shared by `qdmeta run`, `qdmeta resume` and `qdmeta experiment`.
#include <filesystem>
#include <string>

#include "qdmeta/experiment/build.hpp"
#include "qdmeta/experiment/checkpoint.hpp"

namespace qdmeta {

// Files whose presence means a directory holds a run.
const std::vector<std::string>& run_files();

// Makes `out` ready for a new run: refuses (InputError) a directory that holds one unless
// `overwrite`, in which case the old run's files go. Then writes config.toml: the resolved
// config plus a [provenance] table (program version, config file, threads).
void start_run_directory(const std::filesystem::path& out, const BuiltRun& built, const std::string& config_file,
                         int threads, bool overwrite);

struct ResumableRun {
  BuiltRun built;
  RunCursor cursor;
};

// Rebuilds the run in `dir` from its config.toml and loads its checkpoint. InputError when the
// run has finished, cannot checkpoint, or its checkpoint is missing, damaged or mismatched.
ResumableRun open_for_resume(const std::filesystem::path& dir);

}  // namespace qdmeta
