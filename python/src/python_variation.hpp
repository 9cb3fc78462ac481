#pragma once
// A variation operator written in Python for MAP-Elites (qdmeta.Algorithm(..., variation=f)):
// f(parents, partners, seed) -> offspring, the arrays float32 (batch, genotype_size), row r's
// two elites drawn by the algorithm from its own stream, `seed` an int for f's own generator.
// The offspring must be finite and in [0, 1] (InputError naming the row and gene otherwise).
#include <pybind11/pybind11.h>

#include <cstdint>

#include "python_object.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta::python {

class PythonVariation {
 public:
  explicit PythonVariation(pybind11::object function);  // TypeError unless callable
  const SharedPyObject& function() const { return function_; }
  // Called by the algorithm, on any thread, without the GIL.
  void operator()(const RowMatrix& parents, const RowMatrix& partners, std::uint64_t seed, RowMatrix& offspring) const;

 private:
  SharedPyObject function_;
};

}  // namespace qdmeta::python
