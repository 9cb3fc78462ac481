#include "numpy_arrays.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/task.hpp"

namespace py = pybind11;

namespace qdmeta::python {

py::array_t<Real> rows_copy(const Real* data, Index rows, Index cols) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(rows)};
  if (cols >= 0) shape.push_back(static_cast<py::ssize_t>(cols));
  py::array_t<Real> out = new_array<Real>(std::move(shape));
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
  ByteArray out = new_array<std::uint8_t, py::array::c_style | py::array::forcecast>({a.shape(0)});
  const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast> wide = a;
  for (py::ssize_t i = 0; i < out.shape(0); ++i) out.mutable_data()[i] = wide.data()[i] != 0 ? 1 : 0;
  return out;
}

void copy_results(py::handle fitness, py::handle base_features, py::handle valid, const std::string& who,
                  EvaluationView out) {
  const Index n = out.count, nb = out.base_feature_size;
  const FloatArray f = float_rows(fitness, n, -1, who + ": fitness");
  const FloatArray b = float_rows(base_features, n, nb, who + ": base_features");
  std::copy_n(f.data(), n, out.fitness);
  std::copy_n(b.data(), n * nb, out.base_features);
  if (valid.is_none()) {
    std::fill_n(out.valid, n, std::uint8_t{1});
  } else {
    const ByteArray v = flags(valid, n, who + ": valid");
    std::copy_n(v.data(), n, out.valid);
  }
}

void check_result_values(const EvaluationView& out, const std::string& who) {
  for (Index i = 0; i < out.count; ++i) {
    if (!out.valid[i]) continue;
    if (!std::isfinite(out.fitness[i]))
      throw InputError(fmt::format("{} row {}: fitness {} is not finite", who, i, out.fitness[i]));
    for (Index k = 0; k < out.base_feature_size; ++k)
      if (const Real v = out.base_row(i)[k]; !(v >= 0 && v <= 1))
        throw InputError(fmt::format("{} row {}: base feature {} is {}, outside [0, 1]{}", who, i, k, v,
                                     kBaseFeatureRangeHint));
  }
}

}  // namespace qdmeta::python
