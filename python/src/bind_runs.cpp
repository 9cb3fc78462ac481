// qdmeta.run() and qdmeta.resume(): a run directory exactly as `qdmeta run` writes it (config.toml,
// metrics.csv, meta.csv, archive.csv, summary.json, checkpoints), so `qdmeta report`, `qdmeta
// adapt` and the plotting scripts read Python runs too. Ctrl-C ends the run at the next
// generation with a checkpoint, then raises KeyboardInterrupt.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>

#include "bindings.hpp"
#include "python_build.hpp"
#include "python_run.hpp"
#include "qdmeta/io/run_lock.hpp"
#include "qdmeta/run/run_directory.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace qdmeta::python {
namespace {

PythonParts parts_of(std::optional<Task> task, std::shared_ptr<PythonMetaObjective> objective) {
  return PythonParts{std::move(task), std::move(objective)};
}

}  // namespace

void bind_runs(py::module_& m) {
  m.def(
      "run",
      [](const py::dict& config, const fs::path& out_dir, std::optional<Task> task,
         std::shared_ptr<PythonMetaObjective> meta_objective, int threads, bool overwrite, py::object progress) {
        BuiltRun built = build_from_python(config, parts_of(std::move(task), std::move(meta_objective)));
        return start_and_drive(built, out_dir, threads, overwrite, progress);
      },
      py::arg("config"), py::arg("out_dir"), py::arg("task") = py::none(), py::arg("meta_objective") = py::none(),
      py::arg("threads") = 0, py::arg("overwrite") = false, py::arg("progress") = py::none(),
      R"doc(Runs a config dict (the keys of a TOML config) to its budget into out_dir, as `qdmeta run` does,
and returns summary.json as a dict. `task` / `meta_objective`: your own (qdmeta.Task,
qdmeta.MetaObjective). `progress(dict)` hears evals, budget, generation, wall_seconds,
num_elites, obj_max and qd_score after every generation. Ctrl-C ends the run with a checkpoint
(then KeyboardInterrupt); qdmeta.resume() continues it.)doc");

  m.def(
      "resume",
      [](const fs::path& out_dir, std::optional<Task> task, std::shared_ptr<PythonMetaObjective> meta_objective,
         int threads, py::object progress) {
        const RunLock lock(out_dir, RunLock::Mode::kExclusive);
        ResumableRun r = open_for_resume(out_dir, parts_for_resume(out_dir, parts_of(task, meta_objective)));
        return drive(r.built, out_dir, threads, progress, &r.cursor);
      },
      py::arg("out_dir"), py::arg("task") = py::none(), py::arg("meta_objective") = py::none(), py::arg("threads") = 0,
      py::arg("progress") = py::none(),
      R"doc(Continues an interrupted or killed run from its checkpoint, to the bits it would have had
without the stop. A Python task or meta-objective is passed again (the same name); the rest
comes from the run's config.toml.)doc");
}

}  // namespace qdmeta::python
