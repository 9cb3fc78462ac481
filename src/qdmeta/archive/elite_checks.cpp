#include "qdmeta/archive/elite_checks.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

void check_restored_elites(const EliteTable& t, std::string_view what) {
  const auto refuse = [&](Index row, const char* value_kind, Real value, const char* rule) {
    throw InputError(fmt::format("{} is damaged: elite {} (cell {}) has {} {}, where {}", what, row,
                                 t.index[static_cast<std::size_t>(row)], value_kind, value, rule));
  };
  // Written so that NaN fails them.
  const auto unit = [](Real v) { return v >= 0 && v <= 1; };
  const auto signed_unit = [](Real v) { return v >= -1 && v <= 1; };
  for (Index i = 0; i < t.size(); ++i) {
    for (Index j = 0; j < t.solutions.cols(); ++j)
      if (!unit(t.solutions(i, j))) refuse(i, "a gene", t.solutions(i, j), "every gene must lie in [0, 1]");
    for (Index j = 0; j < t.base_features.cols(); ++j)
      if (!signed_unit(t.base_features(i, j)))
        refuse(i, "a base feature", t.base_features(i, j), "every stored base feature must lie in [-1, 1]");
  }
}

}  // namespace qdmeta
