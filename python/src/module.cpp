// The extension module qdmeta._qdmeta; python/qdmeta/__init__.py re-exports it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
#include "python_interrupt.hpp"
#include "qdmeta/cli/builtin_plugins.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/notice.hpp"
#include "qdmeta/core/version.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_qdmeta, m) {
  m.doc() = "qdmeta: Quality-Diversity Meta-Evolution (QD-Meta), CVT-MAP-Elites, AURORA and MAP-Elites";
  qdmeta::register_builtin_plugins();
  // Notices (e.g. CVT's "this can take minutes") reach the user as the command line's do: on
  // stderr, written from C++ so that no thread needs the GIL for them.
  if (!qdmeta::has_notice_sink()) qdmeta::set_notice_sink(qdmeta::print_notice_to_stderr);

  // qdmeta.Error (a RuntimeError) for failures; qdmeta.InputError (an Error and a ValueError)
  // for bad input. Module-lifetime references, never released.
  static PyObject* error = PyErr_NewException("qdmeta.Error", PyExc_RuntimeError, nullptr);
  static PyObject* input_error = PyErr_NewException(
      "qdmeta.InputError", py::make_tuple(py::handle(error), py::handle(PyExc_ValueError)).release().ptr(), nullptr);
  m.attr("Error") = py::handle(error);
  m.attr("InputError") = py::handle(input_error);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const qdmeta::python::PythonInterrupt& e) {
      e.restore();  // the KeyboardInterrupt itself, after the step was undone
    } catch (const qdmeta::InputError& e) {
      PyErr_SetString(input_error, e.what());
    } catch (const qdmeta::Error& e) {
      PyErr_SetString(error, e.what());
    }
  });

  m.attr("__version__") = std::string(qdmeta::kVersion);
  py::dict build;
#ifdef QDMETA_WITH_RHEX
  build["rhex"] = true;
#else
  build["rhex"] = false;
#endif
  build["mpi"] = false;  // MPI runs go through the CLI (mpirun ... qdmeta run)
  build["native"] = QDMETA_PYTHON_NATIVE != 0;
  build["build_type"] = QDMETA_PYTHON_BUILD_TYPE;
  build["pybind11"] = std::to_string(PYBIND11_VERSION_MAJOR) + "." + std::to_string(PYBIND11_VERSION_MINOR) + "." +
                      std::to_string(PYBIND11_VERSION_PATCH);
  m.attr("build_info") = build;

  qdmeta::python::bind_tasks(m);
  qdmeta::python::bind_archives(m);
  qdmeta::python::bind_emitters(m);
  qdmeta::python::bind_schedulers(m);
  qdmeta::python::bind_algorithms(m);
  qdmeta::python::bind_runs(m);
  qdmeta::python::bind_metrics(m);
  qdmeta::python::bind_proximity_archive(m);
  qdmeta::python::bind_sliding_boundaries_archive(m);

  m.def("algorithms", &qdmeta::registered_algorithm_names, "The registered algorithms, the config's default first");
  m.def("tasks", &qdmeta::registered_task_names, "The registered tasks (built-in and registered from Python)");
}
