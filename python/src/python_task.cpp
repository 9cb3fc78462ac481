#include "python_task.hpp"

#include <fmt/format.h>

#include "numpy_arrays.hpp"
#include "python_interrupt.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {

PythonTask::PythonTask(py::object function, Index genotype_size, Index base_feature_size, std::string name,
                       double qd_offset)
    : function_(std::move(function)),
      genotype_size_(genotype_size),
      base_feature_size_(base_feature_size),
      name_(std::move(name)),
      qd_offset_(qd_offset) {
  if (!PyCallable_Check(function_.get().ptr())) throw py::type_error("Task: the function must be callable");
  if (genotype_size_ < 1) throw py::value_error(fmt::format("Task '{}': genotype_size must be >= 1", name_));
  if (base_feature_size_ < 1) throw py::value_error(fmt::format("Task '{}': base_feature_size must be >= 1", name_));
  if (name_.empty()) throw py::value_error("Task: the name must not be empty");
}

void PythonTask::evaluate(GenotypeView genotypes, EvaluationView out) const {
  const py::gil_scoped_acquire gil;
  const Index n = genotypes.count;
  // A fresh array, not a view of qdmeta's buffer: a function may keep what it is given (a log
  // of genotypes), and the copy costs far less than the call.
  const py::object result =
      call_python([&] { return function_.get()(rows_copy(genotypes.data, n, genotypes.genotype_size)); });
  const std::string who = fmt::format("task '{}'", name_);
  if (!py::isinstance<py::tuple>(result) && !py::isinstance<py::list>(result))
    throw py::type_error(fmt::format("{} must return (fitness, base_features) or (fitness, base_features, valid), "
                                     "got {}",
                                     who, py::str(py::type::handle_of(result)).cast<std::string>()));
  const py::sequence parts = result;
  if (parts.size() != 2 && parts.size() != 3)
    throw py::value_error(fmt::format("{} returned {} values; expected (fitness, base_features) or (fitness, "
                                      "base_features, valid)",
                                      who, parts.size()));
  copy_results(parts[0], parts[1], parts.size() == 3 ? py::object(parts[2]) : py::object(py::none()), who, out);
  // The values, checked as tell() checks them and with its exception (qdmeta.InputError): a
  // bad value is the caller's mistake whether their function returned it in a run or they
  // passed it to tell() (Task::evaluate's own check, an Error, is for a built-in task's bug).
  check_result_values(out, who);
}

}  // namespace qdmeta::python
