#include "qdmeta/core/params.hpp"

#include <fmt/format.h>

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

}  // namespace qdmeta::detail
