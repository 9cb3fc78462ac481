#pragma once
// CSV output. Floats are printed in their shortest form that reads back to the same bits.
#include <filesystem>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta {

// archive.csv in pyribs's column convention: index,objective,measures_0..,solution_0..
// (+ base_0.. when the table has base features). Written atomically.
void write_elites_csv(const std::filesystem::path& path, const EliteTable& elites);

// What reading an archive file accepts: every value finite (any table written by
// write_elites_csv), or also every gene and base feature in [0, 1], as a run's archive holds
// them (what the test phase evaluates, so it must not trust a hand-edited file).
enum class EliteValues { kFinite, kRunArchive };

// Parsed back (for tests, adapt and reports): the same table. LF or CRLF line endings. Any bad
// value is an InputError naming file, line, column and rule.
EliteTable read_elites_csv(const std::filesystem::path& path, EliteValues rules = EliteValues::kFinite);

// One CSV line: the cells joined by commas, then a newline.
std::string csv_line(const std::vector<std::string>& cells);

// A CSV file appended to row by row, each row flushed whole, so a crash loses at most the
// row being written.
class CsvAppender {
 public:
  // Starts the file anew with `header`.
  CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header);
  // Continues a file (a resumed run): cut to its first `keep_bytes` bytes, which must hold at
  // least the header, then appended to.
  CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header, std::uint64_t keep_bytes);
  // What the continuing constructor checks, changing nothing: the file exists, holds at least
  // `keep_bytes` bytes and starts with `header`. InputError otherwise.
  static void check_continuable(const std::filesystem::path& path, const std::vector<std::string>& header,
                                std::uint64_t keep_bytes);
  void row(const std::vector<std::string>& cells);
  // Bytes in the file so far, header included.
  std::uint64_t bytes() const { return bytes_; }

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_;
  std::uint64_t bytes_ = 0;
};

}  // namespace qdmeta
