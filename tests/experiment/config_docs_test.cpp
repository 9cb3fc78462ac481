// docs/config.md against the code: every key that the config readers read, with its type,
// default and range as the checks enforce them (ScopedConfigKeyLog), must be a row of the
// reference with those very columns, and (when every optional task is built) every row must be a
// key the code reads. So the reference cannot drift from the checks.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "experiment/config_kinds.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

struct DocRow {
  std::string key, type, fallback, range, meaning;
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
                    c[4], c[2].find('`') != std::string::npos, number});
  }
  return rows;
}

bool matches(const DocRow& row, const ConfigKeyRecord& r) {
  const bool range = row.range == r.range || row.range.starts_with(r.range + "; ");
  // A key read through a descriptor (core/params.hpp) carries its meaning: the row must state it.
  const bool meaning = r.doc.empty() || row.meaning == r.doc;
  return row.key == r.key && row.type == r.type && (!row.fallback_in_code || row.fallback == r.fallback) && range &&
         meaning;
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
        fmt::format("| `{}` | {} | `{}` | {} | {} |", r.key.substr(r.key.rfind('.') + 1), r.type, r.fallback, r.range,
                    r.doc.empty() ? "..." : r.doc);
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
