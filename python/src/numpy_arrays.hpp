#pragma once
// numpy arrays in and out of qdmeta's float32 row-major blocks: views where the layout allows,
// and checked conversions that name the argument, its expected shape and what it got.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta::python {

using FloatArray = pybind11::array_t<Real, pybind11::array::c_style | pybind11::array::forcecast>;
using ByteArray = pybind11::array_t<std::uint8_t, pybind11::array::c_style | pybind11::array::forcecast>;

// A read-only (rows x cols) view of `data`, kept alive by `owner` (None: the caller guarantees
// the data outlives every use of the view).
pybind11::array_t<Real> rows_view(const Real* data, Index rows, Index cols, pybind11::handle owner);
// A copy, as a new (rows x cols) float32 array; cols < 0 makes a vector of `rows`.
pybind11::array_t<Real> rows_copy(const Real* data, Index rows, Index cols);

// `value` as a C-contiguous float32 array of shape (rows, cols) (cols < 0: (rows,)); a
// ValueError names `what` when it is not numeric or has another shape. rows < 0 accepts any
// row count.
FloatArray float_rows(pybind11::handle value, Index rows, Index cols, const std::string& what);
// `value` as rows flags (bool or integer, nonzero is true) of shape (rows,).
ByteArray flags(pybind11::handle value, Index rows, const std::string& what);

// "(3, 2)" for an array's shape.
std::string shape_of(const pybind11::array& a);

}  // namespace qdmeta::python
