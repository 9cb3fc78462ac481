#pragma once
// Ctrl-C inside a Python task or meta-objective: the KeyboardInterrupt raised in the callback
// (by a SIGINT that came while it ran, or while C++ worked and was noticed at its first line)
// crosses C++ as a StepInterrupted, so that step() undoes the step and a run ends at the last
// generation boundary with its files; the module's exception translator then raises the
// KeyboardInterrupt itself again, traceback and all.
#include <pybind11/pybind11.h>

#include <memory>
#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta::python {

class PythonInterrupt : public StepInterrupted {
 public:
  explicit PythonInterrupt(pybind11::error_already_set&& e)
      : StepInterrupted("interrupted (KeyboardInterrupt)"),
        error_(std::make_shared<pybind11::error_already_set>(std::move(e))) {}
  // Sets the KeyboardInterrupt as Python's current error; with the GIL.
  void restore() const { error_->restore(); }

 private:
  std::shared_ptr<pybind11::error_already_set> error_;  // shared: exceptions are copied
};

// call() with the GIL held; a KeyboardInterrupt it raises becomes PythonInterrupt.
template <class Call>
auto call_python(Call&& call) {
  try {
    return call();
  } catch (pybind11::error_already_set& e) {
    if (e.matches(PyExc_KeyboardInterrupt)) throw PythonInterrupt(std::move(e));
    throw;
  }
}

}  // namespace qdmeta::python
