#include "qdmeta/experiment/config.hpp"

#include <fmt/format.h>
#include <fmt/std.h>

#include <cmath>
#include <sstream>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

toml::table load_toml(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("config file {} does not exist", path.string()));
  // toml++ reads a directory as an empty file, which would silently run every default.
  if (!std::filesystem::is_regular_file(path))
    throw InputError(fmt::format("config file {} is not a regular file (a directory?): give a TOML file", path.string()));
  try {
    return toml::parse_file(path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", path.string(), e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
}

ConfigReader::ConfigReader(const toml::table& table, std::string source, toml::table& resolved, std::string prefix)
    : table_(table), source_(std::move(source)), resolved_(resolved), prefix_(std::move(prefix)) {}

std::string ConfigReader::qualified(std::string_view key) const {
  return prefix_.empty() ? std::string(key) : prefix_ + "." + std::string(key);
}

void ConfigReader::type_error(std::string_view key, std::string_view expected) const {
  const toml::node* node = table_.get(key);
  std::ostringstream got;
  got << node->type();
  throw InputError(fmt::format("{}: {} must be {}, got a {}", source_, qualified(key), expected, got.str()));
}

const toml::node* ConfigReader::lookup(std::string_view key) {
  known_.emplace(key);
  return table_.get(key);
}

std::int64_t ConfigReader::integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi) {
  std::int64_t value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (!node->is_integer()) type_error(key, "an integer");
    value = node->as_integer()->get();
  }
  if (value < lo || value > hi)
    throw InputError(fmt::format("{}: {} = {} is out of range: must be in [{}, {}]", source_, qualified(key), value, lo, hi));
  resolved_.insert_or_assign(key, value);
  return value;
}

double ConfigReader::number(std::string_view key, double fallback, double lo, double hi) {
  double value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (node->is_integer()) value = static_cast<double>(node->as_integer()->get());
    else if (node->is_floating_point()) value = node->as_floating_point()->get();
    else type_error(key, "a number");
  }
  if (!(value >= lo && value <= hi))
    throw InputError(fmt::format("{}: {} = {} is out of range: must be in [{}, {}]", source_, qualified(key), value, lo, hi));
  resolved_.insert_or_assign(key, value);
  return value;
}

bool ConfigReader::boolean(std::string_view key, bool fallback) {
  bool value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (!node->is_boolean()) type_error(key, "true or false");
    value = node->as_boolean()->get();
  }
  resolved_.insert_or_assign(key, value);
  return value;
}

std::string ConfigReader::string(std::string_view key, std::string_view fallback) {
  std::string value(fallback);
  if (const toml::node* node = lookup(key)) {
    if (!node->is_string()) type_error(key, "a string");
    value = node->as_string()->get();
  }
  resolved_.insert_or_assign(key, value);
  return value;
}

std::vector<std::int64_t> ConfigReader::integers(std::string_view key, const std::vector<std::int64_t>& fallback,
                                                 std::int64_t lo, std::int64_t hi, std::size_t min_size,
                                                 std::size_t max_size) {
  std::vector<std::int64_t> values = fallback;
  if (const toml::node* node = lookup(key)) {
    const toml::array* array = node->as_array();
    if (!array) type_error(key, "an array of integers");
    values.clear();
    for (const toml::node& item : *array) {
      if (!item.is_integer()) type_error(key, "an array of integers");
      values.push_back(item.as_integer()->get());
    }
  }
  if (values.size() < min_size || values.size() > max_size)
    throw InputError(fmt::format("{}: {} has {} entries: must have between {} and {}", source_, qualified(key),
                                 values.size(), min_size, max_size));
  toml::array out;
  for (std::int64_t v : values) {
    if (v < lo || v > hi)
      throw InputError(fmt::format("{}: {} holds {}, out of range: each must be in [{}, {}]", source_, qualified(key), v,
                                   lo, hi));
    out.push_back(v);
  }
  resolved_.insert_or_assign(key, std::move(out));
  return values;
}

ConfigReader ConfigReader::table(std::string_view key) {
  static const toml::table kEmpty;
  const toml::node* node = lookup(key);
  if (node && !node->is_table()) type_error(key, "a table");
  auto [it, inserted] = resolved_.insert_or_assign(key, toml::table{});
  return ConfigReader(node ? *node->as_table() : kEmpty, source_, *it->second.as_table(), qualified(key));
}

void ConfigReader::finish() const {
  for (auto&& [k, v] : table_) {
    if (known_.contains(k.str())) continue;
    std::string valid;
    for (const auto& name : known_) valid += (valid.empty() ? "" : ", ") + name;
    const std::string where = prefix_.empty() ? "at the top level" : "in [" + prefix_ + "]";
    throw InputError(fmt::format("{}: unknown key '{}' {} (valid keys: {})", source_, qualified(k.str()), where,
                                 valid.empty() ? "none" : valid));
  }
}

}  // namespace qdmeta
