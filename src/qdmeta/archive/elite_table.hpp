#pragma once
// An archive's elites as a flat table, in pyribs's column convention (cell index, objective,
// measures, solution, + base features), sorted by cell index; io/ writes it as archive.csv.
#include <cstdint>
#include <vector>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

struct EliteTable {
  std::vector<std::int64_t> index;
  std::vector<Real> objective;
  RowMatrix measures;
  RowMatrix solutions;
  RowMatrix base_features;  // zero columns when the archive keeps none
  Index size() const { return static_cast<Index>(index.size()); }
};

}  // namespace qdmeta
