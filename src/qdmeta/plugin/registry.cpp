#include "qdmeta/plugin/registry.hpp"

#include <fmt/format.h>

namespace qdmeta {

std::string quoted_names(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", n);
  return out;
}

}  // namespace qdmeta
