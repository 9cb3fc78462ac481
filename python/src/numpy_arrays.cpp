#include "numpy_arrays.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace py = pybind11;

namespace qdmeta::python {

py::array_t<Real> rows_view(const Real* data, Index rows, Index cols, py::handle owner) {
  const auto r = static_cast<py::ssize_t>(rows), c = static_cast<py::ssize_t>(cols);
  const auto size = static_cast<py::ssize_t>(sizeof(Real));
  // A base object makes numpy reference the data instead of copying it.
  py::object base = owner.is_none() ? py::object(py::capsule(data, [](void*) {})) : py::reinterpret_borrow<py::object>(owner);
  py::array_t<Real> view({r, c}, {c * size, size}, data, base);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

py::array_t<Real> rows_copy(const Real* data, Index rows, Index cols) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows)};
  if (cols >= 0) shape.push_back(static_cast<py::ssize_t>(cols));
  py::array_t<Real> out(shape);
  std::copy_n(data, rows * std::max<Index>(cols, 1), out.mutable_data());
  return out;
}

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += fmt::format("{}{}", i ? ", " : "", a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

namespace {

std::string expected_shape(Index rows, Index cols) {
  const std::string r = rows < 0 ? "n" : std::to_string(rows);
  return cols < 0 ? fmt::format("({},)", r) : fmt::format("({}, {})", r, cols);
}

py::array numeric_array(py::handle value, const std::string& what) {
  py::array a = py::array::ensure(value);
  if (!a) throw py::type_error(fmt::format("{} must be an array-like of numbers, got {}", what,
                                           py::str(py::type::handle_of(value)).cast<std::string>()));
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
    throw py::type_error(fmt::format("{} must hold numbers, got dtype {}", what, py::str(a.dtype()).cast<std::string>()));
  return a;
}

void check_shape(const py::array& a, Index rows, Index cols, const std::string& what) {
  const py::ssize_t ndim = cols < 0 ? 1 : 2;
  bool ok = a.ndim() == ndim && (rows < 0 || a.shape(0) == rows) && (cols < 0 || a.shape(1) == cols);
  if (!ok)
    throw py::value_error(fmt::format("{} must have shape {}, got {}", what, expected_shape(rows, cols), shape_of(a)));
}

}  // namespace

FloatArray float_rows(py::handle value, Index rows, Index cols, const std::string& what) {
  const py::array a = numeric_array(value, what);
  check_shape(a, rows, cols, what);
  return FloatArray::ensure(a);
}

ByteArray flags(py::handle value, Index rows, const std::string& what) {
  const py::array a = numeric_array(value, what);
  check_shape(a, rows, -1, what);
  if (a.dtype().kind() == 'b') return ByteArray::ensure(a);
  // Integers: nonzero is true, whatever the width.
  ByteArray out(static_cast<py::ssize_t>(rows < 0 ? a.shape(0) : rows));
  const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> wide = a;
  for (py::ssize_t i = 0; i < out.shape(0); ++i) out.mutable_data()[i] = wide.data()[i] != 0 ? 1 : 0;
  return out;
}

}  // namespace qdmeta::python
