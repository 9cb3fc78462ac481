#pragma once
// An output table declared once: each column's name and how to read its value from a record.
// The CSV header, every row and any JSON summary are generated from that one declaration, so a
// column cannot reach the header and be forgotten in the rows.
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace qdmeta {

// A cell keeps its value's type: integers print as integers, doubles in their shortest form
// that reads back to the same bits, and a JSON summary gets numbers as numbers.
using Cell = std::variant<std::int64_t, std::uint64_t, double, std::string>;

std::string cell_text(const Cell& cell);

template <class Record>
struct Column {
  std::string_view name;
  Cell (*value)(const Record&);
  // Its key in a JSON summary, where that differs from `name` (empty: `name`).
  // (from "" rather than {}: GCC 12 left the default constructor undefined in the unity-built io_test)
  std::string_view summary_key = "";
  std::string_view key() const { return summary_key.empty() ? name : summary_key; }
};

template <class Record>
class Table {
 public:
  Table(std::initializer_list<Column<Record>> columns) : columns_(columns) {
    for (const auto& c : columns_) header_.emplace_back(c.name);
  }
  const std::vector<Column<Record>>& columns() const { return columns_; }
  const std::vector<std::string>& header() const { return header_; }
  std::vector<std::string> row(const Record& record) const {
    std::vector<std::string> cells;
    cells.reserve(columns_.size());
    for (const auto& c : columns_) cells.push_back(cell_text(c.value(record)));
    return cells;
  }

 private:
  std::vector<Column<Record>> columns_;
  std::vector<std::string> header_;
};

}  // namespace qdmeta
