#pragma once
// CSV output. Floats are printed in their shortest form that reads back to the same bits.
#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

#include "qdmeta/archive/elite_table.hpp"

namespace qdmeta {

// archive.csv in pyribs's column convention: index,objective,measures_0..,solution_0..
// (+ base_0.. when the table has base features). Written atomically.
void write_elites_csv(const std::filesystem::path& path, const EliteTable& elites);

// What reading an archive file accepts: every value finite (any table written by
// write_elites_csv), or also every gene in [0, 1], every stored base feature in [-1, 1] (2g - 1 under
// qd_meta.database_inputs = "authors-2g-1") and each cell index once, as a
// run's archive holds them (what the test phase evaluates, so it must not trust a hand-edited file).
enum class EliteValues { kFinite, kRunArchive };

// Parsed back (for tests, adapt and reports): the same table. LF or CRLF line endings. Any bad
// value, an empty line, a repeated column name or a last line without its end (a file cut
// short) is an InputError naming file, line, column and rule. tools/run_files.py holds the
// report to the same rules (docs/architecture.md, "One set of checks for run files").
EliteTable read_elites_csv(const std::filesystem::path& path, EliteValues rules = EliteValues::kFinite);

// One CSV line: the cells joined by commas, then a newline.
std::string csv_line(const std::vector<std::string>& cells);

// A CSV file appended to row by row, each row written whole with one write(2), so a crash loses
// at most the row being written. The file is never reached through a planted link. It keeps the
// FNV-1a hash of its bytes, so a checkpoint can tell later whether they were changed.
class CsvAppender {
 public:
  // Starts the file anew with `header` (whatever stood at `path`, a link included, is replaced).
  CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header);
  // Continues a file (a resumed run): cut to its first `keep_bytes` bytes, which must hold at
  // least the header and hash to `keep_hash`, then appended to.
  CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header, std::uint64_t keep_bytes,
              std::uint64_t keep_hash);
  CsvAppender(CsvAppender&& other) noexcept;
  CsvAppender& operator=(CsvAppender&&) = delete;
  ~CsvAppender();
  // What the continuing constructor checks, changing nothing: the file is a regular file (not a link) that
  // holds at least `keep_bytes` bytes, starts with `header`, and its first `keep_bytes` bytes
  // hash to `keep_hash` (rows changed since the checkpoint are found). InputError otherwise.
  static void check_continuable(const std::filesystem::path& path, const std::vector<std::string>& header,
                                std::uint64_t keep_bytes, std::uint64_t keep_hash);
  void row(const std::vector<std::string>& cells);
  // Bytes in the file so far, header included, and their hash.
  std::uint64_t bytes() const { return bytes_; }
  std::uint64_t hash() const { return hash_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::size_t columns_;
  std::uint64_t bytes_ = 0;
  std::uint64_t hash_;
};

}  // namespace qdmeta
