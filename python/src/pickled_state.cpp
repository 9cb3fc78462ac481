#include "pickled_state.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <string>

#include "qdmeta/archive/elite_checks.hpp"
#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// One value in a form that tells every type and boundary apart (a tag, then the value).
void put(BinaryWriter& out, py::handle v) {
  if (v.is_none()) {
    out.tag("none");
  } else if (py::isinstance<py::bool_>(v)) {  // before int: a bool is an int
    out.tag("bool");
    out.boolean(v.cast<bool>());
  } else if (py::isinstance<py::int_>(v)) {
    out.tag("int");
    out.string(py::str(v).cast<std::string>());  // any size
  } else if (py::isinstance<py::float_>(v)) {
    out.tag("float");
    out.value(v.cast<double>());
  } else if (py::isinstance<py::str>(v)) {
    out.tag("str");
    out.string(v.attr("encode")("utf-8", "surrogatepass").cast<std::string>());
  } else if (py::isinstance<py::bytes>(v)) {
    out.tag("bytes");
    out.string(v.cast<std::string>());
  } else if (py::isinstance<py::array>(v)) {
    const auto a = py::reinterpret_borrow<py::array>(v);
    out.tag("array");
    out.string(py::str(a.dtype()).cast<std::string>());
    for (py::ssize_t d = 0; d < a.ndim(); ++d) out.value<std::int64_t>(a.shape(d));
    out.string(a.attr("tobytes")().cast<std::string>());
  } else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    const auto items = py::reinterpret_borrow<py::sequence>(v);
    out.tag("sequence");
    out.value<std::uint64_t>(items.size());
    for (const auto item : items) put(out, item);
  } else if (py::isinstance<py::dict>(v)) {
    const auto items = py::reinterpret_borrow<py::dict>(v);
    out.tag("dict");
    out.value<std::uint64_t>(items.size());
    for (const auto [key, value] : items) {
      put(out, key);
      put(out, value);
    }
  } else {
    throw Error(
        fmt::format("pickling: no checksum for a value of type {}", py::str(py::type::of(v)).cast<std::string>()));
  }
}

}  // namespace

std::uint64_t state_checksum(std::initializer_list<py::handle> parts) {
  BinaryWriter out;
  for (const py::handle part : parts) put(out, part);
  return fnv1a64(out.bytes());
}

void check_state_checksum(py::handle stored, std::uint64_t expected, std::string_view who) {
  if (!py::isinstance<py::int_>(stored) || py::isinstance<py::bool_>(stored))
    throw InputError(fmt::format("{}: the state is not one qdmeta made", who));
  if (!stored.equal(py::int_(expected)))
    throw InputError(fmt::format("{}: the state is damaged (checksum mismatch): its bytes changed since it was pickled",
                                 who));
}

void check_run_elites(const EliteTable& elites, std::string_view who) {
  check_restored_elites(elites, fmt::format("{}: the state", who));
}

}  // namespace qdmeta::python
