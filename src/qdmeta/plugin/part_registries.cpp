#include "qdmeta/plugin/part_registries.hpp"

#include <algorithm>

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
  for (const auto& name : registered)
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  const std::string valid = quoted_names(names);
  const std::string kind = table.string("kind", fallback, valid);
  if (std::find(names.begin(), names.end(), kind) == names.end()) table.not_a_valid_choice("kind", kind, valid);
  return kind;
}

}  // namespace qdmeta
