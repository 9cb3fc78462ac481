#include "elite_arrays.hpp"

#include <fmt/format.h>

#include "numpy_arrays.hpp"

namespace py = pybind11;

namespace qdmeta::python {

// pyribs's column names: index, objective, measures_0.., solution_0.. (+ base_features_0..).
py::dict elite_table_data(const EliteTable& t) {
  py::dict d;
  py::array_t<std::int64_t> index = new_array<std::int64_t>({static_cast<py::ssize_t>(t.size())});
  std::copy(t.index.begin(), t.index.end(), index.mutable_data());
  d["index"] = index;
  d["objective"] = rows_copy(t.objective.data(), t.size(), -1);
  d["measures"] = rows_copy(t.measures.data(), t.size(), t.measures.cols());
  d["solution"] = rows_copy(t.solutions.data(), t.size(), t.solutions.cols());
  if (t.base_features.cols() > 0) d["base_features"] = rows_copy(t.base_features.data(), t.size(), t.base_features.cols());
  return d;
}

py::object elite_table_pandas(const EliteTable& t) {
  py::module_ pandas;
  try {
    pandas = py::module_::import("pandas");
  } catch (const py::error_already_set&) {
    throw py::import_error("as_pandas() needs pandas (Debian: python3-pandas; pip: pandas); data() gives numpy arrays");
  }
  const py::dict data = elite_table_data(t);
  py::dict columns;
  columns["index"] = data["index"];
  columns["objective"] = data["objective"];
  for (const char* block : {"measures", "solution", "base_features"}) {
    if (!data.contains(block)) continue;
    const py::array_t<Real> a = data[block].cast<py::array_t<Real>>();
    for (py::ssize_t j = 0; j < a.shape(1); ++j)
      columns[py::str(fmt::format("{}_{}", block, j))] = a[py::make_tuple(py::slice(0, a.shape(0), 1), j)];
  }
  return pandas.attr("DataFrame")(columns);
}

}  // namespace qdmeta::python
