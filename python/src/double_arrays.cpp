#include "double_arrays.hpp"

#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {

DoubleArray double_rows(py::handle value, py::ssize_t rows, py::ssize_t cols, const std::string& what) {
  DoubleArray a = DoubleArray::ensure(value);
  if (!a) {
    PyErr_Clear();
    throw InputError(what + " must be a numeric array");
  }
  const bool vector = cols < 0;
  const bool fits = vector ? a.ndim() == 1 && (rows < 0 || a.shape(0) == rows)
                           : a.ndim() == 2 && a.shape(1) == cols && (rows < 0 || a.shape(0) == rows);
  if (!fits) {
    const std::string n = rows < 0 ? "n" : std::to_string(rows);
    throw InputError(what + " must have shape " +
                     (vector ? "(" + n + ",)" : "(" + n + ", " + std::to_string(cols) + ")") + ", not " + shape_of(a));
  }
  return a;
}

py::array_t<double> matrix_array(std::span<const double> v, py::ssize_t cols) {
  auto out = new_array<double>({static_cast<py::ssize_t>(v.size()) / cols, cols});
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

}  // namespace qdmeta::python
