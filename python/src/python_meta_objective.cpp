#include "python_meta_objective.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "numpy_arrays.hpp"
#include "python_interrupt.hpp"

namespace py = pybind11;

namespace qdmeta::python {

PythonMetaObjective::PythonMetaObjective(py::object function, std::string name, bool archive)
    : function_(std::move(function)), name_(std::move(name)), archive_(archive) {
  if (!PyCallable_Check(function_.get().ptr())) throw py::type_error("MetaObjective: the function must be callable");
  if (name_.empty()) throw py::value_error("MetaObjective: the name must not be empty");
}

namespace {

py::array_t<Real> copy_of(const RowMatrix& m) { return rows_copy(m.data(), m.rows(), m.cols()); }

// The archive as the function sees it: its genotypes, or (archive=True) a dict of every stored
// field, named as Archive.data() names them.
py::object archive_argument(const MetaArchive& archive, bool whole) {
  if (!whole) return copy_of(archive.genotypes());
  py::dict d;
  d["solution"] = copy_of(archive.genotypes());
  d["objective"] = rows_copy(archive.fitness().data(), archive.size(), -1);
  d["measures"] = copy_of(archive.measures());
  d["base_features"] = copy_of(archive.base_features());
  return d;
}

}  // namespace

MetaPlan PythonMetaObjective::plan(const MetaArchive& archive, Rng& rng) const {
  // 63 bits, so that numpy.random.default_rng(seed) takes it as it is.
  const auto seed = static_cast<std::int64_t>(rng() >> 1);
  const py::gil_scoped_acquire gil;
  const py::object argument = archive_argument(archive, archive_);
  const py::object result = call_python([&] { return function_.get()(argument, seed); });
  const std::string who = fmt::format("meta-objective '{}'", name_);
  MetaFitnessResult r;
  try {
    if (py::isinstance<py::tuple>(result) && py::len(result) == 2) {
      const py::tuple t = result;
      r.value = t[0].cast<double>();
      r.evaluations = t[1].cast<std::int64_t>();
    } else {
      r.value = result.cast<double>();  // a tuple of another length fails here too
    }
  } catch (const py::cast_error&) {
    throw py::type_error(fmt::format("{} must return a number, or (number, evaluations); got {}", who,
                                     py::repr(result).cast<std::string>()));
  }
  if (!std::isfinite(r.value))
    throw py::value_error(fmt::format("{} returned {}, which is not finite", who, r.value));
  if (r.evaluations < 0) throw py::value_error(fmt::format("{} reported {} evaluations", who, r.evaluations));
  return MetaPlan{{}, r};
}

MetaFitnessResult PythonMetaObjective::score(const MetaArchive&, const MetaPlan& plan,
                                             std::span<const EvaluationBatch>) const {
  return std::any_cast<MetaFitnessResult>(plan.state);
}

}  // namespace qdmeta::python
