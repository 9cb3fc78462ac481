// docs/config.md against the code: every key that the config readers read, with its type,
// default and range as the checks enforce them (ScopedConfigKeyLog), must be a row of the
// reference with those very columns, and (when every optional task is built) every row must be a
// key the code reads. So the reference cannot drift from the checks.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/plugin/config.hpp"
#ifdef QDMETA_TEST_RHEX
#include "qdmeta/tasks/rhex/rhex_config.hpp"
#endif

namespace qdmeta {
namespace {

// Every kind of run a config can describe: each algorithm with each of its alternatives.
std::vector<std::string> every_kind_of_config() {
  std::vector<std::string> tasks = {"rastrigin"};
#ifdef QDMETA_TEST_RHEX
  tasks.push_back("rhex");
#endif
  std::vector<std::string> configs;
  for (const std::string& task : tasks) {
    const std::string head = "[task]\nname = \"" + task + "\"\n";
    for (const char* mutation : {"gaussian", "discrete-step", "uniform-resample", "iso-line"})
      configs.push_back(head + "[mutation]\nkind = \"" + mutation + "\"\n");
    configs.push_back("algorithm = \"map-elites\"\n" + head);
    for (const char* points : {"uniform", "random-descriptors"})
      configs.push_back("algorithm = \"cvt-map-elites\"\n" + head + "[cvt]\npoints = \"" + points + "\"\ncache = false\n");
    // Keys read only where written (so older runs' resolved configs stay as they were).
    configs.push_back("algorithm = \"cvt-map-elites\"\n" + head + "[cvt]\ncache = false\ncentroids_file = \"unread.dat\"\n");
    configs.push_back("algorithm = \"qd-meta\"\n" + head + "[qd_meta]\ndatabase_inputs = \"authors-2g-1\"\n[cma_es]\nsmall_population = \"authors\"\n");
    configs.push_back("algorithm = \"qd-meta\"\n" + head + "[qd_meta]\nbottom_level = \"cma-mae\"\n");
    configs.push_back("algorithm = \"aurora\"\n" + head);
    for (const char* emitters : {"cma-me", "cma-mae"}) {
      configs.push_back("algorithm = \"" + std::string(emitters) + "\"\n" + head);
      configs.push_back("algorithm = \"" + std::string(emitters) + "\"\n" + head +
                        "[emitters]\nrestart_rule = \"every-n\"\n[archive]\nkind = \"cvt\"\n[cvt]\ncache = false\n");
    }
    const std::vector<std::string> metas =
        task == "rastrigin" ? std::vector<std::string>{"translation", "dimension"} : std::vector<std::string>{"damage", "obstacle"};
    for (const std::string& meta : metas)
      for (const char* control : {"sarsa", "static"})
        configs.push_back("algorithm = \"qd-meta\"\n" + head + "[meta_fitness]\nkind = \"" + meta + "\"\n[control]\nkind = \"" +
                          control + "\"\n");
  }
  return configs;
}

std::vector<ConfigKeyRecord> keys_the_code_reads() {
#ifdef QDMETA_TEST_RHEX
  register_rhex_task();
#endif
  std::vector<ConfigKeyRecord> log;
  {
    const ScopedConfigKeyLog recording(log);
    for (const std::string& text : every_kind_of_config()) {
      const toml::table config = toml::parse(text);
      build_run(config, "generated", {}, BuildScope::kTasksOnly);
    }
  }
  // QDMETA_DUMP_CONFIG_KEYS=FILE: the log as TSV, to update the reference from.
  if (const char* dump = std::getenv("QDMETA_DUMP_CONFIG_KEYS")) {
    std::ofstream out(dump);
    for (const auto& r : log) out << r.key << '\t' << r.type << '\t' << r.fallback << '\t' << r.range << '\n';
  }
  return log;
}

struct DocRow {
  std::string key, type, fallback, range;
  bool fallback_in_code;  // in backticks: compared; prose ("drawn from the seed") is not
  int line;
};

std::string without_backticks(std::string s) {
  std::erase(s, '`');
  return s;
}

std::vector<std::string> cells_of(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '|' && line[i - 1] != '\\') {
      const auto a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
      cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

// The rows of docs/config.md's key tables, keys qualified by their section ("## `[cvt]` ...").
std::vector<DocRow> documented_keys() {
  std::ifstream in(std::string(QDMETA_SOURCE_DIR) + "/docs/config.md");
  std::vector<DocRow> rows;
  std::string line, section;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.starts_with("## ")) {
      const auto open = line.find("`[");
      section = open == std::string::npos ? "" : line.substr(open + 2, line.find("]`", open) - open - 2);
      continue;
    }
    if (!line.starts_with("| `")) continue;
    const auto c = cells_of(line);
    if (c.size() < 5) continue;
    const std::string key = without_backticks(c[0]);
    rows.push_back({section.empty() ? key : section + "." + key, c[1], without_backticks(c[2]), without_backticks(c[3]),
                    c[2].find('`') != std::string::npos, number});
  }
  return rows;
}

bool matches(const DocRow& row, const ConfigKeyRecord& r) {
  const bool range = row.range == r.range || row.range.starts_with(r.range + "; ");
  return row.key == r.key && row.type == r.type && (!row.fallback_in_code || row.fallback == r.fallback) && range;
}

TEST(ConfigDocs, EveryKeyTheCodeReadsIsARowWithItsTypeDefaultAndRange) {
  const auto code = keys_the_code_reads();
  const auto docs = documented_keys();
  ASSERT_GT(code.size(), 50u);
  ASSERT_GT(docs.size(), 50u);
  std::set<std::string> reported;
  for (const ConfigKeyRecord& r : code) {
    if (r.key == "provenance") continue;
    bool documented = false, found = false;
    for (const DocRow& row : docs) {
      documented = documented || row.key == r.key;
      found = found || matches(row, r);
    }
    const std::string expected =
        fmt::format("| `{}` | {} | `{}` | {} | ... |", r.key.substr(r.key.rfind('.') + 1), r.type, r.fallback, r.range);
    if (!found && reported.insert(expected).second)
      ADD_FAILURE() << (documented ? "docs/config.md's row differs from the code for " : "docs/config.md lacks ") << r.key
                    << ": the code reads\n  " << expected;
  }
}

TEST(ConfigDocs, EveryRowIsAKeyTheCodeReads) {
#ifndef QDMETA_TEST_RHEX
  GTEST_SKIP() << "built without the RHex task: its rows cannot be checked";
#else
  const auto code = keys_the_code_reads();
  for (const DocRow& row : documented_keys()) {
    bool found = false;
    for (const ConfigKeyRecord& r : code) found = found || matches(row, r);
    EXPECT_TRUE(found) << "docs/config.md:" << row.line << ": `" << row.key << "` (" << row.type << ", " << row.fallback
                       << ", " << row.range << ") is not what the code reads";
  }
#endif
}

}  // namespace
}  // namespace qdmeta
