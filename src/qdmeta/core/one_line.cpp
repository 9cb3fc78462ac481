#include "qdmeta/core/one_line.hpp"

#include <fmt/format.h>

namespace qdmeta {
namespace {

std::string escaped(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte != 0x7f) {
      out += c;
      continue;
    }
    switch (c) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: out += fmt::format("\\x{:02x}", byte);
    }
  }
  return out;
}

bool continuation_byte(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

}  // namespace

std::string one_line(std::string_view text, std::size_t max_bytes) {
  std::string line = escaped(text);
  constexpr std::string_view kCut = "...";
  if (line.size() <= max_bytes || max_bytes <= kCut.size()) return line;
  // Three quarters of the room for the start, the rest for the end; neither splits a character.
  const std::size_t room = max_bytes - kCut.size();
  std::size_t head = room - room / 4;
  std::size_t tail_start = line.size() - room / 4;
  while (head > 0 && continuation_byte(line[head])) --head;
  while (tail_start < line.size() && continuation_byte(line[tail_start])) ++tail_start;
  return line.substr(0, head) + std::string(kCut) + line.substr(tail_start);
}

}  // namespace qdmeta
