#pragma once
// A task written in Python: a callable taking a read-only (batch x genotype_size) float32 array
// and returning (fitness, base_features) or (fitness, base_features, valid). Any numeric dtype
// is accepted and converted; shapes are checked and named in the error. It models UserTask, so
// `Task(PythonTask(...))` runs wherever a C++ task does.
#include <pybind11/pybind11.h>

#include <string>

#include "python_object.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta::python {

class PythonTask {
 public:
  PythonTask(pybind11::object function, Index genotype_size, Index base_feature_size, std::string name,
             double qd_offset);

  std::string name() const { return name_; }
  Index genotype_size() const { return genotype_size_; }
  Index base_feature_size() const { return base_feature_size_; }
  double qd_offset() const { return qd_offset_; }
  // One instance serves every thread: calls take the GIL, so they run one at a time.
  bool shareable() const { return true; }
  // A Python exception reaches Python as raised (the function sees whole batches: no row to name).
  static constexpr bool kOwnErrors = true;
  // Takes the GIL. A Python exception raised by the function propagates as
  // pybind11::error_already_set (its traceback kept), a KeyboardInterrupt as PythonInterrupt
  // (python_interrupt.hpp); a bad result is a pybind11::value_error.
  void evaluate(GenotypeView genotypes, EvaluationView out) const;

  const pybind11::object& function() const { return function_.get(); }

 private:
  SharedPyObject function_;
  Index genotype_size_;
  Index base_feature_size_;
  std::string name_;
  double qd_offset_;
};

// True when `task` wraps a PythonTask (the evaluator then calls it once per batch).
inline bool is_python_task(const Task& task) { return task.target<PythonTask>() != nullptr; }

}  // namespace qdmeta::python
