#include "qdmeta/io/table.hpp"

#include <fmt/format.h>

namespace qdmeta {

std::string cell_text(const Cell& cell) {
  return std::visit([](const auto& value) { return fmt::format("{}", value); }, cell);
}

}  // namespace qdmeta
