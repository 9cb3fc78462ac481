#pragma once
// A run's config as a Python dict, exactly the TOML file's tables and keys (docs/config.md):
// dicts are tables, lists arrays, and bool, int, float and str values. The reader then checks
// every key as it checks a file's, naming it in its messages.
#include <pybind11/pybind11.h>

#include <toml++/toml.h>

namespace qdmeta::python {

// TypeError naming the key path for a value TOML cannot hold (None, an object, a non-str key);
// InputError for an int outside TOML's 64 bits, a str (key or value) with a lone surrogate or
// a NUL (python_text.hpp), a dict or list that contains itself, or one nested more than 64
// levels deep.
toml::table table_from_dict(const pybind11::dict& config);
pybind11::dict dict_from_table(const toml::table& table);

}  // namespace qdmeta::python
