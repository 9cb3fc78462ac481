#include "python_text.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {

std::string checked_text(py::handle value, std::string_view what) {
  if (!py::isinstance<py::str>(value))
    throw py::type_error(
        fmt::format("{} must be a str, not {}", what, py::str(py::type::of(value)).cast<std::string>()));
  Py_ssize_t size = 0;
  const char* data = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (data == nullptr) {
    PyErr_Clear();
    throw InputError(fmt::format("{} holds a lone surrogate (a code point in U+D800..U+DFFF), which is not text: "
                                 "give valid Unicode",
                                 what));
  }
  std::string text(data, static_cast<std::size_t>(size));
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw InputError(fmt::format("{} holds a NUL character (at byte {}), which qdmeta's text cannot hold", what, nul));
  return text;
}

}  // namespace qdmeta::python
