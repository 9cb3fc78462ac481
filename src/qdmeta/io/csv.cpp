#include "qdmeta/io/csv.hpp"

#include <unistd.h>

#include <fmt/compile.h>
#include <fmt/format.h>
#include <fmt/std.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "qdmeta/core/binary_io.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/io/atomic_file.hpp"
#include "qdmeta/io/regular_file.hpp"

namespace qdmeta {

void write_elites_csv(const std::filesystem::path& path, const EliteTable& elites) {
  AtomicFile file(path);
  fmt::memory_buffer buf;
  const auto out = fmt::appender(buf);
  fmt::format_to(out, "index,objective");
  for (Index j = 0; j < elites.measures.cols(); ++j) fmt::format_to(out, ",measures_{}", j);
  for (Index j = 0; j < elites.solutions.cols(); ++j) fmt::format_to(out, ",solution_{}", j);
  for (Index j = 0; j < elites.base_features.cols(); ++j) fmt::format_to(out, ",base_{}", j);
  fmt::format_to(out, "\n");
  // Compiled formats straight into the buffer: the same shortest round-trip text as "{}", without
  // parsing a format string per value (10,000 rows x 20+ values; bench/README.md, issue 16).
  const auto values = [&](const RowMatrix& m, Index i) {
    for (Index j = 0; j < m.cols(); ++j) fmt::format_to(out, FMT_COMPILE(",{}"), m(i, j));
  };
  buf.reserve(static_cast<std::size_t>(elites.size()) *
              static_cast<std::size_t>(16 + 12 * (elites.measures.cols() + elites.solutions.cols() +
                                                  elites.base_features.cols())));
  for (Index i = 0; i < elites.size(); ++i) {
    const auto u = static_cast<std::size_t>(i);
    fmt::format_to(out, FMT_COMPILE("{},{}"), elites.index[u], elites.objective[u]);
    values(elites.measures, i);
    values(elites.solutions, i);
    values(elites.base_features, i);
    buf.push_back('\n');
  }
  file.write(std::string_view(buf.data(), buf.size()));
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

// Reads one line, without its line ending (LF or CRLF: a file edited on Windows reads the same).
bool read_line(std::istream& in, std::string& line) {
  if (!std::getline(in, line)) return false;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return true;
}

// One cell of an archive file, named in every message by file, line and column.
struct CellPlace {
  const std::filesystem::path& path;
  std::size_t line;
  std::size_t column;  // 1-based
  const std::string& name;
  std::string where() const { return fmt::format("{}:{}: column {} ({})", path, line, column, name); }
};

template <class T>
T parse_number(const std::string& text, const CellPlace& at) {
  T value{};
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range)
    throw InputError(fmt::format("{}: '{}' is out of range of a {}", at.where(), text,
                                 std::is_integral_v<T> ? "64-bit integer" : "32-bit float"));
  if (ec != std::errc() || ptr != text.data() + text.size())
    throw InputError(fmt::format("{}: '{}' is not a number", at.where(), text));
  return value;
}

// Genes live in [0, 1]; stored base features in [-1, 1] (the task's are in [0, 1], but QD-Meta
// with qd_meta.database_inputs = "authors-2g-1" stores 2g - 1); fitness and measures need only
// be finite.
enum class CellRule { kFinite, kUnit, kSignedUnit };

Real parse_value(const std::string& text, const CellPlace& at, CellRule rule) {
  const Real v = parse_number<Real>(text, at);
  if (!std::isfinite(v)) throw InputError(fmt::format("{}: '{}' is not finite: every value must be", at.where(), text));
  if (rule == CellRule::kUnit && !(v >= 0 && v <= 1))
    throw InputError(fmt::format("{}: {} is outside [0, 1], where every gene must lie", at.where(), text));
  if (rule == CellRule::kSignedUnit && !(v >= -1 && v <= 1))
    throw InputError(fmt::format("{}: {} is outside [-1, 1], where every stored base feature must lie", at.where(), text));
  return v;
}

}  // namespace

EliteTable read_elites_csv(const std::filesystem::path& path, EliteValues rules) {
  const std::string text = read_regular_file(path, kMaxTableFileBytes);
  // The writer ends every line: a last line without its end is a file cut short, whose last
  // cell may still parse (0.1 of 0.123).
  if (!text.empty() && text.back() != '\n')
    throw InputError(fmt::format("{}:{}: the last line has no line end: the file was cut short", path,
                                 std::count(text.begin(), text.end(), '\n') + 1));
  std::istringstream in(text);
  std::string line;
  if (!read_line(in, line)) throw InputError(fmt::format("{} is empty", path));
  const auto header = split(line);
  if (header.size() < 2 || header[0] != "index" || header[1] != "objective")
    throw InputError(fmt::format("{}: not an archive file (header must start with index,objective)", path));
  for (std::size_t c = 1; c < header.size(); ++c)
    if (std::find(header.begin(), header.begin() + static_cast<std::ptrdiff_t>(c), header[c]) !=
        header.begin() + static_cast<std::ptrdiff_t>(c))
      throw InputError(fmt::format("{}:1: column {} '{}' repeats an earlier column's name", path, c + 1, header[c]));
  // The header's order is the writer's: index, objective, measures_*, solution_*, base_*.
  Index counts[3] = {0, 0, 0};  // measures, solutions, base features
  static constexpr std::string_view kGroups[3] = {"measures_", "solution_", "base_"};
  int group = 0;
  for (std::size_t c = 2; c < header.size(); ++c) {
    while (group < 3 && !header[c].starts_with(kGroups[group])) ++group;
    if (group == 3)
      throw InputError(fmt::format("{}:1: column {} ('{}') is not measures_*, solution_* or base_* in that order", path,
                                   c + 1, header[c]));
    ++counts[group];
  }
  const Index nm = counts[0], ns = counts[1], nb = counts[2];
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;
  for (std::size_t number = 2; read_line(in, line); ++number) {
    // The writer writes no empty line: one is damage (split() would make it a row of one cell).
    if (line.empty()) throw InputError(fmt::format("{}:{}: an empty line: the file is damaged", path, number));
    rows.push_back(split(line));
    line_numbers.push_back(number);
  }
  EliteTable t;
  const auto count = static_cast<Index>(rows.size());
  std::unordered_map<std::int64_t, std::size_t> first_line;  // of each cell (a run's archive: one elite per cell)
  t.measures.resize(count, nm);
  t.solutions.resize(count, ns);
  t.base_features.resize(count, nb);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    const std::size_t number = line_numbers[r];
    if (cells.size() != header.size())
      throw InputError(fmt::format("{}:{}: {} columns, the header has {}", path, number, cells.size(), header.size()));
    const auto at = [&](std::size_t c) { return CellPlace{path, number, c + 1, header[c]}; };
    const auto index = parse_number<std::int64_t>(cells[0], at(0));
    if (index < 0) throw InputError(fmt::format("{}: {} is negative: a cell index must be >= 0", at(0).where(), index));
    if (rules == EliteValues::kRunArchive) {
      const auto [seen, fresh] = first_line.try_emplace(index, number);
      if (!fresh)
        throw InputError(fmt::format("{}: cell {} repeats line {}: a run's archive holds one elite per cell",
                                     at(0).where(), index, seen->second));
    }
    t.index.push_back(index);
    t.objective.push_back(parse_value(cells[1], at(1), CellRule::kFinite));
    const auto i = static_cast<Index>(r);
    std::size_t c = 2;
    for (Index j = 0; j < nm; ++j, ++c) t.measures(i, j) = parse_value(cells[c], at(c), CellRule::kFinite);
    const bool run = rules == EliteValues::kRunArchive;
    for (Index j = 0; j < ns; ++j, ++c)
      t.solutions(i, j) = parse_value(cells[c], at(c), run ? CellRule::kUnit : CellRule::kFinite);
    for (Index j = 0; j < nb; ++j, ++c)
      t.base_features(i, j) = parse_value(cells[c], at(c), run ? CellRule::kSignedUnit : CellRule::kFinite);
  }
  return t;
}

std::string csv_line(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += cells[i];
  }
  line += '\n';
  return line;
}

CsvAppender::CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header)
    : path_(path), fd_(create_file_replacing(path)), columns_(header.size()), hash_(kFnv1a64Basis) {
  row(header);
}

void CsvAppender::check_continuable(const std::filesystem::path& path, const std::vector<std::string>& header,
                                    std::uint64_t keep_bytes, std::uint64_t keep_hash) {
  refuse_symbolic_link(path);  // read through, it would pass here and be refused only when opened to append
  const std::string bytes = read_regular_file(path, kMaxTableFileBytes);
  if (bytes.size() < keep_bytes)
    throw InputError(fmt::format("{} holds {} bytes but the checkpoint expects at least {}: it was changed or lost",
                                 path, bytes.size(), keep_bytes));
  const std::string expected = csv_line(header);  // with its newline
  if (!std::string_view(bytes).starts_with(expected) || keep_bytes < expected.size())
    throw InputError(fmt::format("{} does not start with the expected header: it was changed", path));
  if (fnv1a64(std::string_view(bytes).substr(0, keep_bytes)) != keep_hash)
    throw InputError(fmt::format("{}: its first {} bytes differ from those the checkpoint saw: the file was changed "
                                 "since, so the run cannot continue it",
                                 path, keep_bytes));
}

CsvAppender::CsvAppender(const std::filesystem::path& path, const std::vector<std::string>& header,
                         std::uint64_t keep_bytes, std::uint64_t keep_hash)
    : path_(path), columns_(header.size()), bytes_(keep_bytes), hash_(keep_hash) {
  check_continuable(path, header, keep_bytes, keep_hash);
  fd_ = open_file_for_append(path);
  if (::ftruncate(fd_, static_cast<off_t>(keep_bytes)) != 0) {
    const int error = errno;
    ::close(fd_);
    throw Error(fmt::format("cannot cut {} to {} bytes: {}", path, keep_bytes, std::strerror(error)));
  }
}

CsvAppender::CsvAppender(CsvAppender&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      columns_(other.columns_),
      bytes_(other.bytes_),
      hash_(other.hash_) {}

CsvAppender::~CsvAppender() {
  if (fd_ >= 0) ::close(fd_);
}

void CsvAppender::row(const std::vector<std::string>& cells) {
  if (cells.size() != columns_)
    throw Error(fmt::format("{}: row of {} cells, the header has {}", path_, cells.size(), columns_));
  const std::string line = csv_line(cells);
  write_all(fd_, line, path_);
  bytes_ += line.size();
  hash_ = fnv1a64(line, hash_);
}

}  // namespace qdmeta
