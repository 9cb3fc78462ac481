#pragma once
// What the user reads must be one line of bounded length, whatever a config, a path or a damaged
// file put into a message: the CLI (and the notice printer) passes every message through this
// once, where it prints it, instead of each message guarding the values it quotes.
#include <cstddef>
#include <string>
#include <string_view>

namespace qdmeta {

// The longest message one_line() returns: far above any message of qdmeta's own (a path of
// PATH_MAX fits), far below a 50 MB value echoed whole.
inline constexpr std::size_t kMaxMessageBytes = 8192;

// `text` as one line: control characters (a newline, a tab, an escape sequence, a NUL) written as
// C escapes (\n, \t, \x1b), then, past `max_bytes`, its middle cut out and replaced by "..." (the
// start says what failed, the end often what to do). UTF-8 sequences are never cut in two.
std::string one_line(std::string_view text, std::size_t max_bytes = kMaxMessageBytes);

}  // namespace qdmeta
