// qdmeta.Task (a Python function, or a built-in task made from its config table) and
// qdmeta.MetaObjective. Both pickle: a Python function by reference (its module and name, as
// pickle does), a built-in task as its resolved [task] table.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "configured_task.hpp"
#include "numpy_arrays.hpp"
#include "python_build.hpp"
#include "python_meta_objective.hpp"
#include "python_task.hpp"
#include "python_text.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/config.hpp"
#include "qdmeta/experiment/task_registry.hpp"
#include "toml_convert.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// A built-in (or registered) task from its [task] table, e.g. {"name": "rastrigin", "dimensions": 20}.
Task task_from_table(const py::dict& table) {
  py::dict config;
  config["task"] = table;
  const BuiltRun built = build_from_python(config, {}, BuildScope::kTasksOnly);
  return Task(ConfiguredTask(built.evaluation_tasks.front(), *built.resolved["task"].as_table()));
}

// Pickling: ("python", function, genotype_size, base_feature_size, name, qd_offset) or
// ("builtin", resolved [task] table).
py::tuple task_state(const Task& task) {
  if (const auto* p = task.target<PythonTask>())
    return py::make_tuple("python", p->function(), p->genotype_size(), p->base_feature_size(), p->name(),
                          p->qd_offset());
  if (const toml::table* table = builtin_table(task)) return py::make_tuple("builtin", dict_from_table(*table));
  throw py::type_error(fmt::format("cannot pickle task '{}': only a Task(function, ...) or a Task.builtin(table) "
                                   "pickles (pickle the config that made this one)",
                                   task.name()));
}

Task task_from_state(const py::tuple& s) {
  const std::string kind = s.size() > 0 && py::isinstance<py::str>(s[0]) ? s[0].cast<std::string>() : "";
  if (kind == "python" && s.size() == 6)
    return Task(PythonTask(s[1], s[2].cast<Index>(), s[3].cast<Index>(), s[4].cast<std::string>(),
                           s[5].cast<double>()));
  if (kind == "builtin" && s.size() == 2) return task_from_table(s[1].cast<py::dict>());
  throw InputError("unpickling a qdmeta.Task: the state is not one qdmeta made");
}

py::tuple evaluate(const Task& task, const py::handle& genotypes) {
  const FloatArray g = float_rows(genotypes, -1, task.genotype_size(), "genotypes");
  const Index n = g.shape(0);
  // Genes live in [0, 1] (a task maps them to its own ranges): a gene outside is a mistake
  // the task would silently extrapolate from.
  for (Index i = 0; i < n * task.genotype_size(); ++i)
    if (!(g.data()[i] >= 0 && g.data()[i] <= 1))
      throw InputError(fmt::format("genotypes row {} gene {} is {}, outside [0, 1]", i / task.genotype_size(),
                                   i % task.genotype_size(), g.data()[i]));
  EvaluationBatch out;
  out.resize(n, task.base_feature_size());
  {
    const py::gil_scoped_release release;
    task.evaluate({g.data(), n, task.genotype_size()}, out.view());
  }
  py::array_t<bool> valid = new_array<bool>({static_cast<py::ssize_t>(n)});
  for (Index i = 0; i < n; ++i) valid.mutable_data()[i] = out.valid[static_cast<std::size_t>(i)] != 0;
  return py::make_tuple(rows_copy(out.fitness.data(), n, -1),
                        rows_copy(out.base_features.data(), n, task.base_feature_size()), valid);
}

}  // namespace

void bind_tasks(py::module_& m) {
  py::class_<Task>(m, "Task", R"doc(
A task: evaluates a batch of genotypes (one per row, genes in [0, 1]) into fitness, base
features in [0, 1] and a valid flag per row.

Task(function, genotype_size, base_feature_size, name="python", qd_offset=0.0) wraps a Python
function f(genotypes: float32 array (n, genotype_size)) -> (fitness (n,), base_features
(n, base_feature_size)[, valid (n,)]). Task.builtin({"name": "rastrigin", ...}) makes a
built-in task from its [task] table (docs/config.md).)doc")
      .def(py::init([](py::object function, Index genotype_size, Index base_feature_size, py::handle name,
                       double qd_offset) {
             return Task(PythonTask(std::move(function), genotype_size, base_feature_size,
                                    checked_text(name, "Task(): name"), qd_offset));
           }),
           py::arg("function"), py::arg("genotype_size"), py::arg("base_feature_size"), py::arg("name") = "python",
           py::arg("qd_offset") = 0.0)
      .def_static("builtin", &task_from_table, py::arg("table"),
                  "A built-in task from its [task] table, e.g. {'name': 'rastrigin', 'dimensions': 20}")
      .def_property_readonly("name", &Task::name)
      .def_property_readonly("genotype_size", &Task::genotype_size)
      .def_property_readonly("base_feature_size", &Task::base_feature_size)
      .def_property_readonly("qd_offset", &Task::qd_offset)
      .def_property_readonly("is_python", [](const Task& t) { return is_python_task(t); })
      .def("evaluate", &evaluate, py::arg("genotypes"),
           "Evaluates genotypes (n, genotype_size), every gene in [0, 1]: (fitness, base_features, valid), checked "
           "as in a run")
      .def(py::pickle(&task_state, &task_from_state))
      .def("__repr__", [](const Task& t) {
        return fmt::format("qdmeta.Task('{}', genotype_size={}, base_feature_size={})", t.name(), t.genotype_size(),
                           t.base_feature_size());
      });

  py::class_<PythonMetaObjective, std::shared_ptr<PythonMetaObjective>>(m, "MetaObjective", R"doc(
A meta-objective for QD-Meta, written in Python: function(elites, seed) -> meta-fitness (higher
is better), or (meta-fitness, evaluations spent). `elites` is a float32 array, one elite
genotype per row; `seed` an integer for the function's own random draws (the same run gives the
same seeds). With archive=True the function gets, in place of `elites`, a dict of what the
archive stored for them, one row per elite: "solution", "objective", "measures" (the feature-map's
output) and "base_features", as Archive.data() names them, so that it need not evaluate an elite
again to know its fitness. Given to qdmeta.run() or qdmeta.Algorithm() it becomes the
[meta_fitness] kind `name` of the run's task.)doc")
      .def(py::init([](py::object function, py::handle name, bool archive) {
             std::string text = checked_text(name, "MetaObjective(): name");
             return std::make_shared<PythonMetaObjective>(std::move(function), std::move(text), archive);
           }),
           py::arg("function"), py::arg("name") = "python", py::kw_only(), py::arg("archive") = false)
      .def_property_readonly("name", &PythonMetaObjective::name)
      .def_property_readonly("archive", &PythonMetaObjective::reads_archive)
      .def(py::pickle(
          [](const PythonMetaObjective& o) { return py::make_tuple(o.function(), o.name(), o.reads_archive()); },
          [](const py::tuple& s) {
            // (function, name), as made before `archive` existed, or (function, name, archive).
            if (s.size() < 2 || s.size() > 3 || !py::isinstance<py::str>(s[1]) ||
                (s.size() == 3 && !py::isinstance<py::bool_>(s[2])))
              throw InputError("unpickling a qdmeta.MetaObjective: the state is not one qdmeta made");
            return std::make_shared<PythonMetaObjective>(s[0], s[1].cast<std::string>(),
                                                         s.size() == 3 && s[2].cast<bool>());
          }));
}

}  // namespace qdmeta::python
