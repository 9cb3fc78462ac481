#pragma once
// A Python object that C++ values (tasks, meta-objectives, registry entries) may hold and copy
// freely, on any thread: copies share one reference, and the last copy drops it under the GIL.
// After the interpreter has shut down (a static registry destroyed at exit) it is leaked, since
// touching it then would crash.
#include <pybind11/pybind11.h>

#include <memory>
#include <utility>

namespace qdmeta::python {

class SharedPyObject {
 public:
  SharedPyObject() = default;
  explicit SharedPyObject(pybind11::object o)
      : object_(new pybind11::object(std::move(o)), [](pybind11::object* p) {
          if (Py_IsInitialized() != 0 && _Py_IsFinalizing() == 0) {
            const pybind11::gil_scoped_acquire gil;
            delete p;
          } else {
            p->release();  // the interpreter is gone: leak the reference
            delete p;
          }
        }) {}

  // The object; call only with the GIL held.
  const pybind11::object& get() const { return *object_; }
  explicit operator bool() const { return object_ != nullptr; }

 private:
  std::shared_ptr<pybind11::object> object_;
};

}  // namespace qdmeta::python
