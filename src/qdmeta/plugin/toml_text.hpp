#pragma once
// A config's text checked before toml++ parses it. toml++ stops at the first NUL byte (a
// damaged file would read as "all defaults") and recurses once per level of a table header or
// dotted key ([a.a.a. ... .a] 100,000 deep exhausts the stack); it bounds only the nesting of
// values. So the text is scanned first, strings and comments skipped, and refused with one line
// naming source, line and column.
#include <string_view>

#include <toml++/toml.h>

namespace qdmeta {

// The most parts a key or table header may have ([a.b.c] has 3), and the deepest nesting of
// arrays and inline tables: far above any config, far below what could exhaust a stack.
inline constexpr int kMaxKeyParts = 32;
inline constexpr int kMaxValueNesting = 32;

// InputError "<source>:<line>:<column>: ..." for a NUL byte, a key of more than kMaxKeyParts
// parts or values nested deeper than kMaxValueNesting.
void check_toml_text(std::string_view text, std::string_view source);

// check_toml_text, then toml++'s parse; a syntax error is an InputError naming source, line and
// column.
toml::table parse_toml_text(std::string_view text, std::string_view source);

}  // namespace qdmeta
