#include "toml_convert.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "python_text.hpp"
#include "qdmeta/core/error.hpp"

namespace py = pybind11;

namespace qdmeta::python {
namespace {

// Configs are two or three tables deep; the bound keeps a hostile dict (100,000 levels) from
// overflowing the C++ stack, and the path of open containers catches one that holds itself.
constexpr std::size_t kMaxDepth = 64;

std::string joined(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
// A key path for a message: its start when it is long (a deep nesting repeats itself).
std::string named(const std::string& path) {
  if (path.empty()) return "the config";
  return "'" + (path.size() <= 60 ? path : path.substr(0, 60) + "...") + "'";
}

class Converter {
 public:
  toml::table table_of(const py::dict& dict, const std::string& path) {
    const Open open(*this, dict, path);
    toml::table t;
    for (const auto& [k, v] : dict) {
      if (!py::isinstance<py::str>(k))
        throw py::type_error(
            fmt::format("config: key {} under '{}' is not a string", py::repr(k).cast<std::string>(), path));
      const std::string name =
          checked_text(k, fmt::format("config: key {} under {}", py::repr(k).cast<std::string>(), named(path)));
      convert(v, joined(path, name), [&](auto&& node) { t.insert_or_assign(name, std::forward<decltype(node)>(node)); });
    }
    return t;
  }

 private:
  // A dict or list being converted: on the path while open, refused when met again inside itself.
  class Open {
   public:
    Open(Converter& c, py::handle container, const std::string& path) : c_(c) {
      for (PyObject* p : c_.path_)
        if (p == container.ptr()) throw InputError(fmt::format("config: {} contains itself", named(path)));
      if (c_.path_.size() >= kMaxDepth)
        throw InputError(fmt::format("config: {} is nested more than {} levels deep", named(path), kMaxDepth));
      c_.path_.push_back(container.ptr());
    }
    ~Open() { c_.path_.pop_back(); }
    Open(const Open&) = delete;
    Open& operator=(const Open&) = delete;

   private:
    Converter& c_;
  };

  toml::array array_of(const py::sequence& sequence, const std::string& path) {
    const Open open(*this, sequence, path);
    toml::array a;
    for (const auto& v : sequence)
      convert(v, path, [&](auto&& node) { a.push_back(std::forward<decltype(node)>(node)); });
    return a;
  }

  // A Python int as TOML's 64-bit integer, or an InputError naming the key and the range.
  static std::int64_t integer(py::handle value, const std::string& path) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (overflow != 0)
      throw InputError(fmt::format("config: {} = {} is out of range: a config integer must be in [{}, {}]", path,
                                   py::str(value).cast<std::string>(), std::numeric_limits<std::int64_t>::min(),
                                   std::numeric_limits<std::int64_t>::max()));
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    return v;
  }

  // bool before int: Python's bool is an int.
  template <class Put>
  void convert(py::handle value, const std::string& path, Put&& put) {
    if (py::isinstance<py::bool_>(value)) {
      put(toml::value<bool>(value.cast<bool>()));
    } else if (py::isinstance<py::int_>(value)) {
      put(toml::value<std::int64_t>(integer(value, path)));
    } else if (py::isinstance<py::float_>(value)) {
      put(toml::value<double>(value.cast<double>()));
    } else if (py::isinstance<py::str>(value)) {
      put(toml::value<std::string>(checked_text(value, fmt::format("config: {}", named(path)))));
    } else if (py::isinstance<py::dict>(value)) {
      put(table_of(py::reinterpret_borrow<py::dict>(value), path));
    } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
      put(array_of(py::reinterpret_borrow<py::sequence>(value), path));
    } else if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype")) {
      // A numpy array or scalar: tolist() gives nested lists of Python numbers, or one number
      // (item() would refuse an array of more than one element).
      convert(value.attr("tolist")(), path, put);
    } else {
      throw py::type_error(fmt::format("config: '{}' is {}, which a TOML config cannot hold", path,
                                       py::repr(value).cast<std::string>()));
    }
  }

  std::vector<PyObject*> path_;  // the dicts and lists open above the value being converted
};

py::object to_python(const toml::node& node) {
  if (const auto* t = node.as_table()) return dict_from_table(*t);
  if (const auto* a = node.as_array()) {
    py::list l;
    for (const auto& v : *a) l.append(to_python(v));
    return l;
  }
  if (const auto* v = node.as_boolean()) return py::bool_(v->get());
  if (const auto* v = node.as_integer()) return py::int_(v->get());
  if (const auto* v = node.as_floating_point()) return py::float_(v->get());
  if (const auto* v = node.as_string()) return py::str(v->get());
  return py::none();  // dates and times: qdmeta's configs have none
}

}  // namespace

toml::table table_from_dict(const py::dict& config) { return Converter().table_of(config, ""); }

py::dict dict_from_table(const toml::table& table) {
  py::dict d;
  for (const auto& [k, v] : table) d[py::str(std::string(k.str()))] = to_python(v);
  return d;
}

}  // namespace qdmeta::python
