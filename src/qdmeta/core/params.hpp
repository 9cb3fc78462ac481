#pragma once
// Helpers for XxxParams::validate(): each names the field, the value and the rule it breaks.
#include <fmt/format.h>

#include <array>
#include <string>
#include <string_view>
#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

template <class T>
void require_range(std::string_view field, T value, T lo, T hi) {
  if (!(value >= lo && value <= hi))
    throw InputError(fmt::format("{} = {} is out of range: must be in [{}, {}]", field, value, lo, hi));
}

template <class T>
void require_at_least(std::string_view field, T value, T lo) {
  if (!(value >= lo)) throw InputError(fmt::format("{} = {} is out of range: must be at least {}", field, value, lo));
}

// Enum <-> string tables: every choice is an enum; an unknown name lists the valid ones.
template <class E, std::size_t N>
using EnumNames = std::array<std::pair<E, std::string_view>, N>;

template <class E, std::size_t N>
std::string_view enum_to_string(const EnumNames<E, N>& names, E value) {
  for (const auto& [e, s] : names)
    if (e == value) return s;
  return "?";
}

template <class E, std::size_t N>
E enum_from_string(const EnumNames<E, N>& names, std::string_view what, std::string_view text) {
  std::string valid;
  for (const auto& [e, s] : names) {
    if (s == text) return e;
    if (!valid.empty()) valid.append(", ");
    valid.append("\"").append(s).append("\"");
  }
  throw InputError(fmt::format("{} = \"{}\" is not a valid choice: use one of {}", what, text, valid));
}

}  // namespace qdmeta
