#include "qdmeta/core/params.hpp"

#include <fmt/format.h>

#include <cmath>

namespace qdmeta::detail {

std::string number_text(std::int64_t value) { return fmt::format("{}", value); }
std::string number_text(std::uint64_t value) { return fmt::format("{}", value); }
std::string number_text(double value) { return fmt::format("{}", value); }
std::string number_text(float value) { return fmt::format("{}", value); }

void throw_out_of_range(std::string_view field, const std::string& value, const std::string& lo, const std::string& hi) {
  throw InputError(fmt::format("{} = {} is out of range: must be in [{}, {}]", field, value, lo, hi));
}

void throw_below(std::string_view field, const std::string& value, const std::string& lo) {
  throw InputError(fmt::format("{} = {} is out of range: must be at least {}", field, value, lo));
}

void throw_invalid_choice(std::string_view what, std::string_view text, const std::string& valid) {
  throw InputError(fmt::format("{} = \"{}\" is not a valid choice: use one of {}", what, text, valid));
}

void throw_outside(const IntParam& p, const std::string& value) {
  throw_out_of_range(fmt::format("{}.{}", p.table, p.key), value, number_text(p.lo), number_text(p.hi));
}

}  // namespace qdmeta::detail

namespace qdmeta {

void require(const RealParam& p, double value) {
  const bool open_lo = p.open == Open::kLower || p.open == Open::kBoth;
  const bool open_hi = p.open == Open::kUpper || p.open == Open::kBoth;
  if (std::isfinite(value) && (open_lo ? value > p.lo : value >= p.lo) && (open_hi ? value < p.hi : value <= p.hi))
    return;
  std::string rule;
  if (p.hi != kNoUpper)
    rule = fmt::format("in {}{}, {}{}", open_lo ? "(" : "[", p.lo, p.hi, open_hi ? ")" : "]");
  else if (p.lo == -kNoUpper)
    rule = "finite";
  else if (open_lo)
    rule = p.lo == 0.0 ? "a positive number" : fmt::format("a number > {}", p.lo);
  else
    rule = fmt::format("a number >= {}", p.lo);
  throw InputError(fmt::format("{}.{} = {} is out of range: must be {}", p.table, p.key, value, rule));
}

}  // namespace qdmeta
