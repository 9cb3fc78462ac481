#pragma once
// The module's parts, one file each: tasks and meta-objectives, archives, algorithms (ask/tell),
// CMA-ME / CMA-MAE emitters, their schedulers, runs (run, resume: run directories as the CLI
// writes them), metrics (the CQD score), the proximity and sliding-boundaries archives.
#include <pybind11/pybind11.h>

namespace qdmeta::python {

void bind_tasks(pybind11::module_& m);
void bind_archives(pybind11::module_& m);
void bind_emitters(pybind11::module_& m);
void bind_schedulers(pybind11::module_& m);
void bind_algorithms(pybind11::module_& m);
void bind_runs(pybind11::module_& m);
void bind_metrics(pybind11::module_& m);
void bind_proximity_archive(pybind11::module_& m);
void bind_sliding_boundaries_archive(pybind11::module_& m);

}  // namespace qdmeta::python
