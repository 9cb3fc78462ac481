#pragma once
// Helpers for XxxParams::validate(): each names the field, the value and the rule it breaks.
// The messages are formatted in params.cpp, so that this public header needs no fmt.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "qdmeta/core/error.hpp"

namespace qdmeta {

namespace detail {
// A number as the messages write it (fmt's shortest round-trip form for floating point).
std::string number_text(std::int64_t value);
std::string number_text(std::uint64_t value);
std::string number_text(double value);
std::string number_text(float value);
template <class T>
std::string text_of(T value) {
  static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>, "a range check is for numbers");
  if constexpr (std::is_floating_point_v<T>) return number_text(value);
  else if constexpr (std::is_signed_v<T>) return number_text(static_cast<std::int64_t>(value));
  else return number_text(static_cast<std::uint64_t>(value));
}
[[noreturn]] void throw_out_of_range(std::string_view field, const std::string& value, const std::string& lo,
                                     const std::string& hi);
[[noreturn]] void throw_below(std::string_view field, const std::string& value, const std::string& lo);
[[noreturn]] void throw_invalid_choice(std::string_view what, std::string_view text, const std::string& valid);
}  // namespace detail

template <class T>
void require_range(std::string_view field, T value, T lo, T hi) {
  if (!(value >= lo && value <= hi))
    detail::throw_out_of_range(field, detail::text_of(value), detail::text_of(lo), detail::text_of(hi));
}

template <class T>
void require_at_least(std::string_view field, T value, T lo) {
  if (!(value >= lo)) detail::throw_below(field, detail::text_of(value), detail::text_of(lo));
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
  detail::throw_invalid_choice(what, text, valid);
}

}  // namespace qdmeta
