#pragma once
// Runs a built run to its budget from Python: into a run directory exactly as `qdmeta run`
// writes it, or in memory. After every generation, with the GIL: pending signals (Ctrl-C) end
// the run at that generation (with a checkpoint when it has a directory) and are raised
// afterwards; `progress(dict)`, when not None, hears how far it is.
#include <pybind11/pybind11.h>

#include <filesystem>
#include <optional>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/run/checkpoint.hpp"

namespace qdmeta::python {

// summary.json as a dict (in memory: its keys that apply). `resume`: the cursor of a checkpoint
// the algorithm was loaded from.
pybind11::dict drive(BuiltRun& built, const std::optional<std::filesystem::path>& out, int threads,
                     const pybind11::object& progress, const RunCursor* resume);

// A new run into `out`, as `qdmeta run` starts one: the directory locked and made ready
// (config.toml with its provenance; an existing run refused unless `overwrite`), then driven.
pybind11::dict start_and_drive(BuiltRun& built, const std::filesystem::path& out, int threads, bool overwrite,
                               const pybind11::object& progress);

}  // namespace qdmeta::python
