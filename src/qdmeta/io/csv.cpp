#include "qdmeta/io/csv.hpp"

#include <fmt/format.h>
#include <fmt/std.h>

#include <charconv>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"

namespace qdmeta {

void write_elites_csv(const std::filesystem::path& path, const EliteTable& elites) {
  AtomicFile file(path);
  fmt::memory_buffer buf;
  auto out = std::back_inserter(buf);
  fmt::format_to(out, "index,objective");
  for (Index j = 0; j < elites.measures.cols(); ++j) fmt::format_to(out, ",measures_{}", j);
  for (Index j = 0; j < elites.solutions.cols(); ++j) fmt::format_to(out, ",solution_{}", j);
  for (Index j = 0; j < elites.base_features.cols(); ++j) fmt::format_to(out, ",base_{}", j);
  fmt::format_to(out, "\n");
  for (Index i = 0; i < elites.size(); ++i) {
    fmt::format_to(out, "{},{}", elites.index[static_cast<std::size_t>(i)], elites.objective[static_cast<std::size_t>(i)]);
    for (Index j = 0; j < elites.measures.cols(); ++j) fmt::format_to(out, ",{}", elites.measures(i, j));
    for (Index j = 0; j < elites.solutions.cols(); ++j) fmt::format_to(out, ",{}", elites.solutions(i, j));
    for (Index j = 0; j < elites.base_features.cols(); ++j) fmt::format_to(out, ",{}", elites.base_features(i, j));
    fmt::format_to(out, "\n");
  }
  file.stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
  file.commit();
}

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

template <class T>
T parse_number(const std::string& text, const std::filesystem::path& path, std::size_t line) {
  T value{};
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw InputError(fmt::format("{}:{}: '{}' is not a number", path, line, text));
  return value;
}

}  // namespace

EliteTable read_elites_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open {}", path));
  std::string line;
  if (!std::getline(in, line)) throw InputError(fmt::format("{} is empty", path));
  const auto header = split(line);
  Index nm = 0, ns = 0, nb = 0;
  for (const auto& h : header) {
    nm += h.starts_with("measures_");
    ns += h.starts_with("solution_");
    nb += h.starts_with("base_");
  }
  if (header.size() < 2 || header[0] != "index" || header[1] != "objective")
    throw InputError(fmt::format("{}: not an archive file (header must start with index,objective)", path));
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line))
    if (!line.empty()) rows.push_back(split(line));
  EliteTable t;
  const auto count = static_cast<Index>(rows.size());
  t.measures.resize(count, nm);
  t.solutions.resize(count, ns);
  t.base_features.resize(count, nb);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    if (cells.size() != header.size())
      throw InputError(fmt::format("{}:{}: {} columns, the header has {}", path, r + 2, cells.size(), header.size()));
    t.index.push_back(parse_number<std::int64_t>(cells[0], path, r + 2));
    t.objective.push_back(parse_number<Real>(cells[1], path, r + 2));
    const auto i = static_cast<Index>(r);
    std::size_t c = 2;
    for (Index j = 0; j < nm; ++j) t.measures(i, j) = parse_number<Real>(cells[c++], path, r + 2);
    for (Index j = 0; j < ns; ++j) t.solutions(i, j) = parse_number<Real>(cells[c++], path, r + 2);
    for (Index j = 0; j < nb; ++j) t.base_features(i, j) = parse_number<Real>(cells[c++], path, r + 2);
  }
  return t;
}

CsvAppender::CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header)
    : path_(path), columns_(header.size()) {
  out_.open(path, std::ios::trunc);
  if (!out_) throw Error(fmt::format("cannot write {}", path));
  row(header);
}

CsvAppender::CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header,
                         std::uint64_t keep_bytes)
    : path_(path), columns_(header.size()) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec || size < keep_bytes)
    throw InputError(fmt::format("{} holds {} bytes but the checkpoint expects at least {}: it was changed or lost",
                                 path, ec ? 0 : size, keep_bytes));
  std::string expected;
  for (std::size_t i = 0; i < header.size(); ++i) expected += (i ? "," : "") + header[i];
  std::ifstream in(path);
  std::string first;
  std::getline(in, first);
  if (first != expected || keep_bytes < expected.size() + 1)
    throw InputError(fmt::format("{} does not start with the expected header: it was changed", path));
  in.close();
  std::filesystem::resize_file(path, keep_bytes, ec);
  if (ec) throw Error(fmt::format("cannot cut {} to {} bytes: {}", path, keep_bytes, ec.message()));
  out_.open(path, std::ios::app);
  if (!out_) throw Error(fmt::format("cannot write {}", path));
  bytes_ = keep_bytes;
}

void CsvAppender::row(const std::vector<std::string>& cells) {
  if (cells.size() != columns_)
    throw Error(fmt::format("{}: row of {} cells, the header has {}", path_, cells.size(), columns_));
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += cells[i];
  }
  line += '\n';
  out_ << line;
  out_.flush();
  bytes_ += line.size();
  if (!out_) throw Error(fmt::format("writing {} failed", path_));
}

}  // namespace qdmeta
