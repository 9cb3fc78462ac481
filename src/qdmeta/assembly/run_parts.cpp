#include "qdmeta/assembly/run_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/standard_tables.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

// A part named as a built-in kind would never be used (the built-in is read first): refused.
void refuse_builtin_name(const ConfigReader& table, std::string_view what, const std::string& kind,
                         const std::vector<std::string>& builtin) {
  if (std::find(builtin.begin(), builtin.end(), kind) != builtin.end())
    throw InputError(fmt::format("{}: the {} part handed over is named \"{}\", a built-in kind: give it another name",
                                 table.source(), what, kind));
}

}  // namespace

std::string read_part_name(ConfigReader& r, std::string_view key, const std::string& part_name) {
  const std::string name = r.string(key, part_name);
  if (name != part_name) r.not_a_valid_choice(key, name, fmt::format("\"{}\"", part_name), " (the part handed over)");
  return name;
}

std::unique_ptr<MetaObjective> read_meta_objective(AlgorithmBuild& b, ConfigReader& meta_fitness) {
  const auto& part = b.parts.meta_objective;
  if (!part) return read_registered_meta_objective(meta_fitness, b.task, b.settings.seed);
  read_part_name(meta_fitness, "kind", part->kind);
  return part->read(meta_fitness, b.task, b.settings.seed);
}

std::unique_ptr<GenerationController> read_controller(AlgorithmBuild& b, ConfigReader& control) {
  const auto& part = b.parts.controller;
  if (!part) return read_control_table(control);
  read_part_name(control, "kind", part->kind);
  return read_control_with(control, part->kind, part->read);
}

std::string read_archive_kind(AlgorithmBuild& b, ConfigReader& archive) {
  const auto& part = b.parts.archive;
  if (!part) return read_archive_kind(archive);
  refuse_builtin_name(archive, "archive", part->kind, {"grid"});
  return read_part_name(archive, "kind", part->kind);
}

AnyArchive read_archive(AlgorithmBuild& b, ConfigReader& archive, const std::string& kind) {
  const auto& part = b.parts.archive;
  if (part && part->kind == kind) return read_archive_with(archive, kind, part->read, b.task, b.built.memory);
  return read_registered_archive(archive, kind, b.task, b.built.memory);
}

std::unique_ptr<FeatureMap> read_feature_map(AlgorithmBuild& b, ConfigReader& feature_map, ConfigReader& archive,
                                             Index targets) {
  const auto& part = b.parts.feature_map;
  if (!part) return read_feature_map_table(feature_map, archive, b.task.base_feature_size(), targets);
  refuse_builtin_name(feature_map, "feature-map", part->kind, {"select"});
  read_part_name(feature_map, "kind", part->kind);
  return read_feature_map_with(feature_map, archive, part->kind, part->read, b.task.base_feature_size(), targets);
}

}  // namespace qdmeta
