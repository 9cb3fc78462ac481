#include "qdmeta/io/centroid_text.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// The numbers of one line; InputError naming the line and the token that is not one.
std::vector<double> parse_line(std::string_view line, std::size_t line_number) {
  std::vector<double> values;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    std::size_t end = i;
    while (end < line.size() && !is_space(line[end])) ++end;
    if (end == i) break;
    const std::string_view token = line.substr(i, end - i);
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size())
      throw InputError(fmt::format("line {}: \"{}\" is not a number", line_number, token));
    values.push_back(value);
    i = end;
  }
  return values;
}

}  // namespace

RowMatrix read_centroid_text(const std::filesystem::path& path, Index count, Index dimensions) {
  const std::string text = read_regular_file(path, kMaxTableFileBytes);
  RowMatrix centroids(count, dimensions);
  Index rows = 0;
  std::size_t line_number = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const std::vector<double> values = parse_line(std::string_view(text).substr(start, end - start), line_number);
    start = end + 1;
    if (values.empty()) continue;
    if (static_cast<Index>(values.size()) != dimensions)
      throw InputError(fmt::format("line {} has {} numbers, expected {} (the task's base features)", line_number,
                                   values.size(), dimensions));
    if (rows == count)
      throw InputError(fmt::format("more than {} centroids (cvt.centroids); line {} is one too many", count, line_number));
    for (Index j = 0; j < dimensions; ++j) {
      const double v = values[static_cast<std::size_t>(j)];
      if (!std::isfinite(v) || v < 0.0 || v > 1.0)
        throw InputError(fmt::format("line {}, column {}: {} is outside the base-feature space [0, 1]", line_number,
                                     j + 1, v));
      centroids(rows, j) = static_cast<Real>(v);
    }
    ++rows;
  }
  if (rows != count)
    throw InputError(fmt::format("{} centroids, expected {} (cvt.centroids)", rows, count));
  return centroids;
}

}  // namespace qdmeta
