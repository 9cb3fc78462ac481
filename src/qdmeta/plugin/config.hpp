#pragma once
// Reading a TOML config with strict checks. Every key read is recorded, with the value in
// force (given or default), into a "resolved" table written beside the results; a key that
// nothing reads is an error that lists the valid keys of its table.
#include <toml++/toml.h>

#include <cstdint>
#include <limits>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/params.hpp"

namespace qdmeta {

// Parses a file; a missing or non-regular file, a NUL byte, keys nested too deep
// (plugin/toml_text.hpp) or a syntax error throws InputError naming file, line, column.
toml::table load_toml(const std::filesystem::path& path);

// Every key a ConfigReader reads, with its type, default and range as the checks enforce them:
// docs/config.md's tables are tested against this log, so the reference cannot drift from the code.
struct ConfigKeyRecord {
  std::string key;       // qualified: "qd_meta.batch_size"
  std::string type;      // "integer", "number", "boolean", "string", "array of integers"
  std::string fallback;  // the default, as TOML: 400, 0.05, "gaussian", [100, 100]
  std::string range;     // e.g. "1 to 10^7", "> 0", "[0, 1]", "\"lloyd\", \"mini-batch\""
  std::string doc;       // the meaning, where read through a descriptor (IntParam, RealParam)
};
// While one is alive, every ConfigReader on this thread appends what it reads to `log`.
class ScopedConfigKeyLog {
 public:
  explicit ScopedConfigKeyLog(std::vector<ConfigKeyRecord>& log);
  ~ScopedConfigKeyLog();
  ScopedConfigKeyLog(const ScopedConfigKeyLog&) = delete;
  ScopedConfigKeyLog& operator=(const ScopedConfigKeyLog&) = delete;

 private:
  std::vector<ConfigKeyRecord>* previous_;
};

// A parameter's range as the key log records it and docs/config.md writes it ("1 to 10^7", "> 0").
std::string range_text(const IntParam& p);
std::string range_text(const RealParam& p);

class ConfigReader {
 public:
  // `source` names the file in messages; `resolved` receives every value in force.
  ConfigReader(const toml::table& table, std::string source, toml::table& resolved, std::string prefix = "");

  // `range_doc`, where given, is the range as docs/config.md states it when the bounds depend on
  // other settings (e.g. "1 to N (task.dimensions)"); it only changes what the key log records.
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi,
                       std::string_view range_doc = {});
  double number(std::string_view key, double fallback, double lo, double hi, Open open = Open::kNone);  // integers accepted
  // The same, for a parameter declared once (core/params.hpp): its key, range and meaning. The
  // descriptor's table must be this reader's.
  std::int64_t integer(const IntParam& p, std::int64_t fallback);
  double number(const RealParam& p, double fallback);
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key, std::string_view fallback, std::string_view range_doc = {});
  std::vector<std::int64_t> integers(std::string_view key, const std::vector<std::int64_t>& fallback, std::int64_t lo,
                                     std::int64_t hi, std::size_t min_size, std::size_t max_size,
                                     std::string_view range_doc = {});
  template <class E, std::size_t N>
  E choice(std::string_view key, E fallback, const EnumNames<E, N>& names) {
    std::vector<std::string_view> choices;
    for (const auto& [e, name] : names) choices.push_back(name);
    const std::string text = read_string(key, enum_to_string(names, fallback));
    record_choice(key, enum_to_string(names, fallback), choices);
    for (const auto& [e, name] : names)
      if (name == text) return e;
    refuse_choice(key, text, choices);
  }
  // An integer that may be absent (nullopt), with no default standing in for it.
  std::optional<std::int64_t> optional_integer(std::string_view key, std::int64_t lo, std::int64_t hi);
  std::vector<std::string> strings(std::string_view key, const std::vector<std::string>& fallback);
  bool has(std::string_view key) const { return table_.contains(key); }
  // An array of tables ([[key]]), one reader each, named key[1], key[2], ... in messages; finish()
  // checks their keys too. Absent: none.
  std::vector<ConfigReader> tables(std::string_view key);
  // A table or an array of tables taken as it is, for a caller that checks its contents itself
  // (an experiment's `set`, its claims); null when absent. Copied to the resolved table as it is.
  const toml::table* raw_table(std::string_view key);
  const toml::array* raw_tables(std::string_view key);
  // A sub-table ([task], [archive], ...); absent means all defaults. This reader remembers it,
  // so that finish() checks its keys too.
  ConfigReader table(std::string_view key);
  // Throws InputError on any key that was never read: in every table opened through this one
  // (in the order they were opened, each checking its own first), then in this one. build_run()
  // calls it on the whole config after the algorithm's builder, so no builder can let a
  // misspelt key through; a reader may call it earlier on its own table.
  void finish() const;
  const std::string& source() const { return source_; }
  // True while a config is only resolved (BuildScope::kResolve): a reader reads and checks its
  // keys as always, then makes nothing (the task it is handed is a shape, core/task_shape.hpp).
  // Tables opened through this reader afterwards inherit it.
  bool resolving() const { return resolving_; }
  void set_resolving(bool resolving) { resolving_ = resolving; }
  // InputError "<source>: <key> = \"<value>\" is not a valid choice: use one of <valid><why>", for
  // a name that no registry holds (`valid` as quoted_names() lists them).
  [[noreturn]] void not_a_valid_choice(std::string_view key, std::string_view value, std::string_view valid,
                                       std::string_view why = {}) const;

 private:
  std::string qualified(std::string_view key) const;
  std::string read_string(std::string_view key, std::string_view fallback);
  void record(std::string_view key, std::string type, std::string fallback, std::string range,
              std::string_view doc = {}) const;
  std::int64_t read_integer(std::string_view key, std::int64_t fallback, std::int64_t lo, std::int64_t hi,
                            std::string range, std::string_view doc);
  double read_number(std::string_view key, double fallback, double lo, double hi, Open open, std::string_view doc);
  void require_table(std::string_view table) const;
  // choice()'s key log entry, and its error (out of line: the messages are formatted there).
  void record_choice(std::string_view key, std::string_view fallback, const std::vector<std::string_view>& choices) const;
  [[noreturn]] void refuse_choice(std::string_view key, std::string_view text,
                                  const std::vector<std::string_view>& choices) const;
  [[noreturn]] void type_error(std::string_view key, std::string_view expected) const;
  const toml::node* lookup(std::string_view key);

  struct Scope;  // the keys read and the tables opened, shared by copies of a reader

  const toml::table& table_;
  std::string source_;
  toml::table& resolved_;
  std::string prefix_;
  std::shared_ptr<Scope> scope_;
  bool resolving_ = false;
};

// Runs `f` (e.g. a task's constructor, which checks its own parameters) and prefixes the
// InputError it may throw with the config file of `table`, as the reader's own messages are.
template <class F>
auto naming_source(const ConfigReader& table, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(table.source() + ": " + e.what());
  }
}

}  // namespace qdmeta
