#pragma once
// Reading a TOML config with strict checks. Every key read is recorded, with the value in
// force (given or default), into a "resolved" table written beside the results; a key that
// nothing reads is an error that lists the valid keys of its table.
#include <toml++/toml.h>

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

// Parses a file; a missing file or a syntax error throws InputError naming file, line, column.
toml::table load_toml(const std::filesystem::path& path);

class ConfigReader {
 public:
  // `source` names the file in messages; `resolved` receives every value in force.
  ConfigReader(const toml::table& table, std::string source, toml::table& resolved, std::string prefix = "");

  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi);
  double number(std::string_view key, double fallback, double lo, double hi);  // integers accepted
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key, std::string_view fallback);
  std::vector<std::int64_t> integers(std::string_view key, const std::vector<std::int64_t>& fallback, std::int64_t lo,
                                     std::int64_t hi, std::size_t min_size, std::size_t max_size);
  template <class E, std::size_t N>
  E choice(std::string_view key, E fallback, const EnumNames<E, N>& names) {
    const std::string text = string(key, enum_to_string(names, fallback));
    try {
      return enum_from_string(names, qualified(key), text);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", source_, e.what()));
    }
  }
  bool has(std::string_view key) const { return table_.contains(key); }
  // A sub-table ([task], [archive], ...); absent means all defaults.
  ConfigReader table(std::string_view key);
  // Throws InputError on any key that was never read. Call after reading everything.
  void finish() const;
  const std::string& source() const { return source_; }

 private:
  std::string qualified(std::string_view key) const;
  [[noreturn]] void type_error(std::string_view key, std::string_view expected) const;
  const toml::node* lookup(std::string_view key);

  const toml::table& table_;
  std::string source_;
  toml::table& resolved_;
  std::string prefix_;
  std::set<std::string, std::less<>> known_;
};

}  // namespace qdmeta
