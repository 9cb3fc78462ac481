#pragma once
// An archive's elites (EliteTable) for Python: numpy arrays under pyribs's names, or a pandas
// DataFrame with pyribs's columns (index, objective, measures_0.., solution_0..).
#include <pybind11/pybind11.h>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta::python {

// index, objective, measures, solution (and base_features when kept), sorted by cell index.
pybind11::dict elite_table_data(const EliteTable& table);
// ImportError saying how to get pandas when it is missing.
pybind11::object elite_table_pandas(const EliteTable& table);

}  // namespace qdmeta::python
