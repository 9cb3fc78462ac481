#pragma once
// CSV output. Floats are printed in their shortest form that reads back to the same bits.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"

namespace qdmeta {

// archive.csv in pyribs's column convention: index,objective,measures_0..,solution_0..
// (+ base_0.. when the table has base features). Written atomically.
void write_elites_csv(const std::filesystem::path& path, const EliteTable& elites);

// Parsed back (for tests, adapt and reports): the same table.
EliteTable read_elites_csv(const std::filesystem::path& path);

// A CSV file appended to row by row, each row flushed whole, so a crash loses at most the
// row being written.
class CsvAppender {
 public:
  CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header);
  void row(const std::vector<std::string>& cells);

 private:
  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_;
};

}  // namespace qdmeta
