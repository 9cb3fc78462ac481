#include "qdmeta/plugin/config.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fmt/std.h>

#include <cmath>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"
#include "qdmeta/plugin/toml_text.hpp"

namespace qdmeta {

toml::table load_toml(const std::filesystem::path& path) {
  if (!path_taken(path)) throw InputError(fmt::format("config file {} does not exist", path.string()));
  // A directory, a FIFO or a device is refused, not read as an empty (all-defaults) config.
  if (!std::filesystem::is_regular_file(path))
    throw InputError(fmt::format("config file {} is not a regular file (a directory?): give a TOML file", path.string()));
  return parse_toml_text(read_regular_file(path, kMaxTextFileBytes), path.string());
}

namespace {

thread_local std::vector<ConfigKeyRecord>* t_key_log = nullptr;

// 10^7 for exact powers of ten from 10^4 on (as docs/config.md writes them), else the digits.
template <class T>
std::string range_number(T x) {
  for (int e = 4; e <= 18; ++e) {
    const double p = std::pow(10.0, e);
    if (static_cast<double>(x) == p) return fmt::format("10^{}", e);
  }
  return fmt::format("{}", x);
}

std::string integer_range(std::int64_t lo, std::int64_t hi) {
  if (hi == std::numeric_limits<std::int64_t>::max()) return fmt::format(">= {}", lo);
  return fmt::format("{} to {}", range_number(lo), range_number(hi));
}

std::string number_range(double lo, double hi, Open open) {
  const bool open_lo = open == Open::kLower || open == Open::kBoth;
  const bool open_hi = open == Open::kUpper || open == Open::kBoth;
  if (hi == kNoUpper) {
    if (lo == -kNoUpper) return "finite";
    return fmt::format("{} {}", open_lo ? ">" : ">=", range_number(lo));
  }
  return fmt::format("{}{}, {}{}", open_lo ? "(" : "[", range_number(lo), range_number(hi), open_hi ? ")" : "]");
}

}  // namespace

std::string range_text(const IntParam& p) { return integer_range(p.lo, p.hi); }
std::string range_text(const RealParam& p) { return number_range(p.lo, p.hi, p.open); }

ScopedConfigKeyLog::ScopedConfigKeyLog(std::vector<ConfigKeyRecord>& log) : previous_(t_key_log) { t_key_log = &log; }
ScopedConfigKeyLog::~ScopedConfigKeyLog() { t_key_log = previous_; }

void ConfigReader::record(std::string_view key, std::string type, std::string fallback, std::string range,
                          std::string_view doc) const {
  if (t_key_log)
    t_key_log->push_back({qualified(key), std::move(type), std::move(fallback), std::move(range), std::string(doc)});
}

namespace {
std::string quoted_list(const std::vector<std::string_view>& choices) {
  std::string out;
  for (std::string_view c : choices) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", c);
  return out;
}
}  // namespace

void ConfigReader::record_choice(std::string_view key, std::string_view fallback,
                                 const std::vector<std::string_view>& choices) const {
  record(key, "string", fmt::format("\"{}\"", fallback), quoted_list(choices));
}

void ConfigReader::refuse_choice(std::string_view key, std::string_view text,
                                 const std::vector<std::string_view>& choices) const {
  throw InputError(fmt::format("{}: {} = \"{}\" is not a valid choice: use one of {}", source_, qualified(key), text,
                               quoted_list(choices)));
}

struct ConfigReader::Scope {
  std::set<std::string, std::less<>> known;  // the keys read
  std::vector<ConfigReader> opened;          // the tables opened through this one, in order
};

ConfigReader::ConfigReader(const toml::table& table, std::string source, toml::table& resolved, std::string prefix)
    : table_(table),
      source_(std::move(source)),
      resolved_(resolved),
      prefix_(std::move(prefix)),
      scope_(std::make_shared<Scope>()) {}

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
  scope_->known.emplace(key);
  return table_.get(key);
}

void ConfigReader::require_table(std::string_view table) const {
  if (table != prefix_)
    throw Error(fmt::format("a parameter of [{}] read from the table \"{}\" (a programming error)", table, prefix_));
}

std::int64_t ConfigReader::integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi,
                                   std::string_view range_doc) {
  return read_integer(key, fallback, lo, hi, range_doc.empty() ? integer_range(lo, hi) : std::string(range_doc), {});
}

std::int64_t ConfigReader::integer(const IntParam& p, std::int64_t fallback) {
  require_table(p.table);
  return read_integer(p.key, fallback, p.lo, p.hi, range_text(p), p.doc);
}

std::int64_t ConfigReader::read_integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi,
                                        std::string range, std::string_view doc) {
  std::int64_t value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (!node->is_integer()) type_error(key, "an integer");
    value = node->as_integer()->get();
  }
  record(key, "integer", fmt::format("{}", fallback), std::move(range), doc);
  if (value < lo || value > hi)
    throw InputError(fmt::format("{}: {} = {} is out of range: must be in [{}, {}]", source_, qualified(key), value, lo, hi));
  resolved_.insert_or_assign(key, value);
  return value;
}

double ConfigReader::number(std::string_view key, double fallback, double lo, double hi, Open open) {
  return read_number(key, fallback, lo, hi, open, {});
}

double ConfigReader::number(const RealParam& p, double fallback) {
  require_table(p.table);
  return read_number(p.key, fallback, p.lo, p.hi, p.open, p.doc);
}

double ConfigReader::read_number(std::string_view key, double fallback, double lo, double hi, Open open,
                                 std::string_view doc) {
  double value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (node->is_integer()) value = static_cast<double>(node->as_integer()->get());
    else if (node->is_floating_point()) value = node->as_floating_point()->get();
    else type_error(key, "a number");
  }
  record(key, "number", fmt::format("{}", fallback), number_range(lo, hi, open), doc);
  const bool open_lo = open == Open::kLower || open == Open::kBoth;
  const bool open_hi = open == Open::kUpper || open == Open::kBoth;
  const bool inside = std::isfinite(value) && (open_lo ? value > lo : value >= lo) && (open_hi ? value < hi : value <= hi);
  if (!inside)
    throw InputError(fmt::format("{}: {} = {} is out of range: must be {}", source_, qualified(key), value,
                                 open == Open::kNone && hi != kNoUpper ? fmt::format("in [{}, {}]", lo, hi)
                                                                       : number_range(lo, hi, open)));
  resolved_.insert_or_assign(key, value);
  return value;
}

bool ConfigReader::boolean(std::string_view key, bool fallback) {
  bool value = fallback;
  if (const toml::node* node = lookup(key)) {
    if (!node->is_boolean()) type_error(key, "true or false");
    value = node->as_boolean()->get();
  }
  record(key, "boolean", fallback ? "true" : "false", "");
  resolved_.insert_or_assign(key, value);
  return value;
}

std::string ConfigReader::string(std::string_view key, std::string_view fallback, std::string_view range_doc) {
  record(key, "string", fmt::format("\"{}\"", fallback), std::string(range_doc));
  return read_string(key, fallback);
}

std::string ConfigReader::read_string(std::string_view key, std::string_view fallback) {
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
                                                 std::size_t max_size, std::string_view range_doc) {
  std::vector<std::int64_t> values = fallback;
  record(key, "array of integers", fmt::format("[{}]", fmt::join(fallback, ", ")),
         !range_doc.empty() ? std::string(range_doc)
                            : fmt::format("{} entries, each {}",
                                          min_size == max_size ? fmt::format("{}", min_size)
                                                               : fmt::format("{} to {}", min_size, max_size),
                                          integer_range(lo, hi)));
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

std::optional<std::int64_t> ConfigReader::optional_integer(std::string_view key, std::int64_t lo, std::int64_t hi) {
  if (!has(key)) {
    (void)lookup(key);  // a known key, absent
    record(key, "integer", "none", integer_range(lo, hi));
    return std::nullopt;
  }
  return integer(key, lo, lo, hi);
}

std::vector<std::string> ConfigReader::strings(std::string_view key, const std::vector<std::string>& fallback) {
  std::vector<std::string> values = fallback;
  std::string quoted;
  for (const auto& v : fallback) quoted += fmt::format("{}\"{}\"", quoted.empty() ? "" : ", ", v);
  record(key, "array of strings", fmt::format("[{}]", quoted), "");
  if (const toml::node* node = lookup(key)) {
    const toml::array* array = node->as_array();
    if (!array) type_error(key, "an array of strings");
    values.clear();
    for (const toml::node& item : *array) {
      if (!item.is_string()) type_error(key, "an array of strings");
      values.push_back(item.as_string()->get());
    }
  }
  toml::array out;
  for (const auto& v : values) out.push_back(v);
  resolved_.insert_or_assign(key, std::move(out));
  return values;
}

std::vector<ConfigReader> ConfigReader::tables(std::string_view key) {
  const toml::node* node = lookup(key);
  const toml::array* array = node ? node->as_array() : nullptr;
  if (node && (!array || !array->is_array_of_tables())) type_error(key, "an array of tables ([[" + std::string(key) + "]])");
  toml::array resolved_tables;
  const std::size_t n = array ? array->size() : 0;
  for (std::size_t i = 0; i < n; ++i) resolved_tables.push_back(toml::table{});
  auto [it, inserted] = resolved_.insert_or_assign(key, std::move(resolved_tables));
  toml::array& out = *it->second.as_array();
  std::vector<ConfigReader> readers;
  for (std::size_t i = 0; i < n; ++i) {
    ConfigReader sub(*(*array)[i].as_table(), source_, *out[i].as_table(), fmt::format("{}[{}]", qualified(key), i + 1));
    sub.resolving_ = resolving_;
    scope_->opened.push_back(sub);
    readers.push_back(std::move(sub));
  }
  return readers;
}

const toml::table* ConfigReader::raw_table(std::string_view key) {
  const toml::node* node = lookup(key);
  if (!node) return nullptr;
  if (!node->is_table()) type_error(key, "a table");
  resolved_.insert_or_assign(key, *node->as_table());
  return node->as_table();
}

const toml::array* ConfigReader::raw_tables(std::string_view key) {
  const toml::node* node = lookup(key);
  if (!node) return nullptr;
  const toml::array* array = node->as_array();
  if (!array || !array->is_array_of_tables()) type_error(key, "an array of tables ([[" + std::string(key) + "]])");
  resolved_.insert_or_assign(key, *array);
  return array;
}

ConfigReader ConfigReader::table(std::string_view key) {
  static const toml::table kEmpty;
  const toml::node* node = lookup(key);
  if (node && !node->is_table()) type_error(key, "a table");
  auto [it, inserted] = resolved_.insert_or_assign(key, toml::table{});
  ConfigReader sub(node ? *node->as_table() : kEmpty, source_, *it->second.as_table(), qualified(key));
  sub.resolving_ = resolving_;
  scope_->opened.push_back(sub);  // a copy sharing sub's scope: what the caller reads, finish() sees
  return sub;
}

void ConfigReader::not_a_valid_choice(std::string_view key, std::string_view value, std::string_view valid,
                                      std::string_view why) const {
  throw InputError(
      fmt::format("{}: {} = \"{}\" is not a valid choice: use one of {}{}", source_, qualified(key), value, valid, why));
}

void ConfigReader::finish() const {
  for (const ConfigReader& sub : scope_->opened) sub.finish();
  const auto& known = scope_->known;
  for (auto&& [k, v] : table_) {
    if (known.contains(k.str())) continue;
    std::string valid;
    for (const auto& name : known) valid += (valid.empty() ? "" : ", ") + name;
    const std::string where = prefix_.empty() ? "at the top level" : "in [" + prefix_ + "]";
    throw InputError(fmt::format("{}: unknown key '{}' {} (valid keys: {})", source_, qualified(k.str()), where,
                                 valid.empty() ? "none" : valid));
  }
}

}  // namespace qdmeta
