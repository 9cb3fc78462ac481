#pragma once
// numpy arrays of doubles in and out of the archives that keep doubles (ProximityArchive,
// SlidingBoundariesArchive), checked in one line that names the argument.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "numpy_arrays.hpp"

namespace qdmeta::python {

using DoubleArray = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;

// `value` as (rows x cols) doubles (cols < 0: a vector of rows; rows < 0: any row count);
// InputError naming `what` and the shape it has otherwise.
DoubleArray double_rows(pybind11::handle value, pybind11::ssize_t rows, pybind11::ssize_t cols, const std::string& what);

inline std::span<const double> values(const DoubleArray& a) { return {a.data(), static_cast<std::size_t>(a.size())}; }

template <class T>
pybind11::array_t<T> vector_array(const std::vector<T>& v) {
  auto out = new_array<T>({static_cast<pybind11::ssize_t>(v.size())});
  std::copy(v.begin(), v.end(), out.mutable_data());
  return out;
}

// A copy of `v` as a (size / cols) x cols array.
pybind11::array_t<double> matrix_array(std::span<const double> v, pybind11::ssize_t cols);

}  // namespace qdmeta::python
