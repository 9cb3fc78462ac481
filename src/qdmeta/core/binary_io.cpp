#include "qdmeta/core/binary_io.hpp"

#include <fmt/format.h>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

void BinaryReader::fail(std::string_view message) const {
  throw InputError(fmt::format("{}: {} (at byte {} of {})", source_, message, position_, bytes_.size()));
}

const char* BinaryReader::take(std::size_t n, std::string_view what) {
  if (n > remaining()) fail(fmt::format("truncated while reading {}", what));
  const char* p = bytes_.data() + position_;
  position_ += n;
  return p;
}

std::size_t BinaryReader::count(std::string_view what, std::size_t element_size) {
  const auto n = value<std::uint64_t>(what);
  if (n > remaining() / element_size) fail(fmt::format("{} claims {} elements, more than the file holds", what, n));
  return static_cast<std::size_t>(n);
}

void BinaryReader::check_shape(std::int64_t rows, std::int64_t cols, std::size_t element_size,
                               std::string_view what) const {
  if (rows < 0 || cols < 0 || (cols > 0 && static_cast<std::uint64_t>(rows) > remaining() / element_size /
                                                                               static_cast<std::uint64_t>(cols)))
    fail(fmt::format("{} has an impossible shape {} x {}", what, rows, cols));
}

std::string BinaryReader::string(std::string_view what) {
  const auto n = count(what, 1);
  return std::string(take(n, what), n);
}

void BinaryReader::expect_tag(std::string_view name) {
  const std::size_t at = position_;
  const std::string got = string(fmt::format("section '{}'", name));
  if (got != name) {
    position_ = at;
    fail(fmt::format("expected section '{}'", name));
  }
}

void BinaryReader::finish() const {
  if (remaining() != 0) fail(fmt::format("{} unexpected bytes after the end", remaining()));
}

}  // namespace qdmeta
