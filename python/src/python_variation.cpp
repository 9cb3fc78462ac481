#include "python_variation.hpp"

#include <fmt/format.h>

#include <cmath>

#include "numpy_arrays.hpp"
#include "python_interrupt.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {

PythonVariation::PythonVariation(py::object function) : function_(std::move(function)) {
  if (!PyCallable_Check(function_.get().ptr()))
    throw py::type_error("Algorithm(variation=...): must be a callable f(parents, partners, seed) -> offspring");
}

void PythonVariation::operator()(const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed,
                                 RowMatrix& offspring) const {
  const py::gil_scoped_acquire gil;
  const Index rows = offspring.rows(), cols = offspring.cols();
  const py::object result = call_python([&] {
    return function_.get()(rows_copy(parents.data(), rows, cols), rows_copy(partners.data(), rows, cols), seed);
  });
  const FloatArray out = float_rows(result, rows, cols, "the variation's offspring");
  const Real* data = out.data();
  for (Index r = 0; r < rows; ++r)
    for (Index k = 0; k < cols; ++k) {
      const Real g = data[r * cols + k];
      if (!(g >= 0.0f && g <= 1.0f))
        throw InputError(fmt::format("the variation's offspring: row {} gene {} is {}, outside [0, 1] (clip it: "
                                     "every gene of a genotype is in [0, 1])",
                                     r, k, g));
      offspring(r, k) = g;
    }
}

}  // namespace qdmeta::python
