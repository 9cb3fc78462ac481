#pragma once
// numpy arrays in and out of qdmeta's float32 row-major blocks: views where the layout allows,
// and checked conversions that name the argument, its expected shape and what it got.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/task.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta::python {

using FloatArray = pybind11::array_t<Real, pybind11::array::c_style | pybind11::array::forcecast>;
using ByteArray = pybind11::array_t<std::uint8_t, pybind11::array::c_style | pybind11::array::forcecast>;

// A new C-contiguous array of `shape`. Its strides are given, from sizeof(T): pybind11 before
// 2.12 would take them from the dtype's itemsize, which it reads at numpy 1's offset in the
// dtype struct, and under numpy 2 gets 0 (every element then reads as the first).
template <class T, int Flags = pybind11::array::forcecast>
pybind11::array_t<T, Flags> new_array(std::vector<pybind11::ssize_t> shape) {
  std::vector<pybind11::ssize_t> strides(shape.size());
  pybind11::ssize_t stride = sizeof(T);
  for (std::size_t d = shape.size(); d-- > 0;) {
    strides[d] = stride;
    stride *= shape[d];
  }
  return pybind11::array_t<T, Flags>(std::move(shape), std::move(strides));
}

// A copy, as a new (rows x cols) float32 array; cols < 0 makes a vector of `rows`.
pybind11::array_t<Real> rows_copy(const Real* data, Index rows, Index cols);

// `value` as a C-contiguous float32 array of shape (rows, cols) (cols < 0: (rows,)); a
// ValueError names `what` when it is not numeric or has another shape. rows < 0 accepts any
// row count.
FloatArray float_rows(pybind11::handle value, Index rows, Index cols, const std::string& what);
// `value` as rows flags (bool or integer, nonzero is true) of shape (rows,).
ByteArray flags(pybind11::handle value, Index rows, const std::string& what);

// One batch's results from Python into `out` (out.count rows): fitness (rows,), base features
// (rows, out.base_feature_size) and valid flags (rows,), or every row valid when `valid` is None;
// each checked as above, `who` naming the caller in the messages.
void copy_results(pybind11::handle fitness, pybind11::handle base_features, pybind11::handle valid,
                  const std::string& who, EvaluationView out);

// Throws InputError naming `who`, the row and the value when a valid row of `out` has a
// non-finite fitness or a base feature outside [0, 1] (the same check as tell()'s).
void check_result_values(const EvaluationView& out, const std::string& who);

// "(3, 2)" for an array's shape.
std::string shape_of(const pybind11::array& a);

}  // namespace qdmeta::python
