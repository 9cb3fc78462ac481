#include "toml_convert.hpp"

#include <fmt/format.h>

#include <string>

namespace py = pybind11;

namespace qdmeta::python {
namespace {

std::string joined(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

void insert_value(toml::table& table, const std::string& key, py::handle value, const std::string& path);
void append_value(toml::array& array, py::handle value, const std::string& path);

toml::table table_of(const py::dict& dict, const std::string& path) {
  toml::table t;
  for (const auto& [k, v] : dict) {
    if (!py::isinstance<py::str>(k))
      throw py::type_error(fmt::format("config: key {} under '{}' is not a string", py::repr(k).cast<std::string>(), path));
    const std::string name = k.cast<std::string>();
    insert_value(t, name, v, joined(path, name));
  }
  return t;
}

toml::array array_of(const py::sequence& sequence, const std::string& path) {
  toml::array a;
  for (const auto& v : sequence) append_value(a, v, path);
  return a;
}

// bool before int: Python's bool is an int.
template <class Put>
void convert(py::handle value, const std::string& path, Put&& put) {
  if (py::isinstance<py::bool_>(value)) {
    put(toml::value<bool>(value.cast<bool>()));
  } else if (py::isinstance<py::int_>(value)) {
    put(toml::value<std::int64_t>(value.cast<std::int64_t>()));
  } else if (py::isinstance<py::float_>(value)) {
    put(toml::value<double>(value.cast<double>()));
  } else if (py::isinstance<py::str>(value)) {
    put(toml::value<std::string>(value.cast<std::string>()));
  } else if (py::isinstance<py::dict>(value)) {
    put(table_of(py::reinterpret_borrow<py::dict>(value), path));
  } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    put(array_of(py::reinterpret_borrow<py::sequence>(value), path));
  } else if (py::hasattr(value, "item") && py::hasattr(value, "dtype")) {  // a numpy scalar
    convert(value.attr("item")(), path, put);
  } else if (py::hasattr(value, "tolist") && py::hasattr(value, "dtype")) {  // a numpy array
    convert(value.attr("tolist")(), path, put);
  } else {
    throw py::type_error(fmt::format("config: '{}' is {}, which a TOML config cannot hold", path,
                                     py::repr(value).cast<std::string>()));
  }
}

void insert_value(toml::table& table, const std::string& key, py::handle value, const std::string& path) {
  convert(value, path, [&](auto&& node) { table.insert_or_assign(key, std::forward<decltype(node)>(node)); });
}

void append_value(toml::array& array, py::handle value, const std::string& path) {
  convert(value, path, [&](auto&& node) { array.push_back(std::forward<decltype(node)>(node)); });
}

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

toml::table table_from_dict(const py::dict& config) { return table_of(config, ""); }

py::dict dict_from_table(const toml::table& table) {
  py::dict d;
  for (const auto& [k, v] : table) d[py::str(std::string(k.str()))] = to_python(v);
  return d;
}

}  // namespace qdmeta::python
