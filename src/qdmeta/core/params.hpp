#pragma once
// Helpers for XxxParams::validate(): each names the field, the value and the rule it breaks.
// The messages are formatted in params.cpp, so that this public header needs no fmt.
#include <array>
#include <cstdint>
#include <limits>
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

// Which ends of a number's range are open: (0, +inf) is {0, kNoUpper, Open::kLower}, "> 0".
enum class Open { kNone, kLower, kUpper, kBoth };
inline constexpr double kNoUpper = std::numeric_limits<double>::max();

// One configuration parameter, declared once beside its params struct: the table and key it is
// read from, its range and its meaning (docs/config.md's column, which the config docs test
// compares). ConfigReader reads with it and validate() checks with it, so that the range a config
// is read with and the range the component accepts cannot drift apart; the struct's member
// initialiser stays the one default.
struct IntParam {
  std::string_view table, key;
  std::int64_t lo, hi;
  std::string_view doc;
  // The same key with a lower bound that depends on another setting (cvt.samples >= centroids).
  constexpr IntParam from(std::int64_t lower) const { return {table, key, lower, hi, doc}; }
};
struct RealParam {  // every value must be finite besides
  std::string_view table, key;
  double lo, hi;
  Open open;
  std::string_view doc;
};

namespace detail {
[[noreturn]] void throw_outside(const IntParam& p, const std::string& value);
}  // namespace detail

// "<table>.<key> = <value> is out of range: must be in [lo, hi]", as require_range writes it.
template <class T>
void require(const IntParam& p, T value) {
  static_assert(std::is_integral_v<T> && !std::is_same_v<T, bool>, "an IntParam is an integer");
  if (std::cmp_less(value, p.lo) || std::cmp_greater(value, p.hi)) detail::throw_outside(p, detail::text_of(value));
}
// As above for a closed range; otherwise "must be in (lo, hi)", "a positive number", "a number >= lo".
void require(const RealParam& p, double value);

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
