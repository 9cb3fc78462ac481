#include "qdmeta/plugin/part_registries.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "qdmeta/core/error.hpp"

#include "qdmeta/plugin/config.hpp"

namespace qdmeta {

Registry<VariationReader>& variation_registry() {
  static Registry<VariationReader> registry;
  return registry;
}

Registry<ControllerReader>& controller_registry() {
  static Registry<ControllerReader> registry;
  return registry;
}

Registry<FeatureMapReader>& feature_map_registry() {
  static Registry<FeatureMapReader> registry;
  return registry;
}

Registry<ArchiveReader>& archive_registry() {
  static Registry<ArchiveReader> registry;
  return registry;
}

std::string read_kind(ConfigReader& table, const std::vector<std::string>& builtin,
                      const std::vector<std::string>& registered, std::string_view fallback) {
  std::vector<std::string> names = builtin;
  for (const auto& name : registered) {
    // A built-in kind is a fast path the algorithms call directly: a plugin of its name would be
    // silently ignored or silently win, so neither happens.
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw InputError(fmt::format("{}: this program registered a part under \"{}\", a built-in kind of this "
                                   "table: register it under another name",
                                   table.source(), name));
    names.push_back(name);
  }
  const std::string valid = quoted_names(names);
  const std::string kind = table.string("kind", fallback, valid);
  if (std::find(names.begin(), names.end(), kind) == names.end()) table.not_a_valid_choice("kind", kind, valid);
  return kind;
}

}  // namespace qdmeta
