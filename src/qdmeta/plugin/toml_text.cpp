#include "qdmeta/plugin/toml_text.hpp"

#include <fmt/format.h>

#include <string>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

bool bare_key_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
         c == '+' || c == ':';
}

// A forward scan that knows where strings and comments begin and end, and so which dots join key
// parts and which brackets nest values. Anything else about TOML is left to the parser.
class TomlScanner {
 public:
  TomlScanner(std::string_view text, std::string_view source) : text_(text), source_(source) {}

  void run() {
    while (at_ < text_.size()) {
      const char c = text_[at_];
      if (c == '\0') fail("a NUL byte: a config is text, and this one is damaged or not a config");
      if (c == '#') {
        skip_to_line_end();
      } else if (c == '"' || c == '\'') {
        skip_string(c);  // a quoted key part keeps its run: "a".b is two parts
      } else if (c == '.') {
        if (++dots_ + 1 > kMaxKeyParts)
          fail(fmt::format("a key or table header of more than {} parts", kMaxKeyParts));
        advance();
      } else if (bare_key_char(c) || c == ' ' || c == '\t') {
        advance();
      } else {
        if (c == '[' || c == '{') {
          if (++nesting_ > kMaxValueNesting)  // a table header's own brackets count too: [[a]] is 2
            fail(fmt::format("arrays or inline tables nested more than {} deep", kMaxValueNesting));
        } else if ((c == ']' || c == '}') && nesting_ > 0) {
          --nesting_;
        }
        dots_ = 0;  // '=', ',', brackets and line ends end a key
        advance();
      }
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(fmt::format("{}:{}:{}: {}", source_, line_, column_, what));
  }

  void advance() {
    if (text_[at_] == '\n') {
      ++line_;
      column_ = 1;
      dots_ = 0;
    } else {
      ++column_;
    }
    ++at_;
  }

  void skip_to_line_end() {
    while (at_ < text_.size() && text_[at_] != '\n') {
      if (text_[at_] == '\0') fail("a NUL byte: a config is text, and this one is damaged or not a config");
      advance();
    }
  }

  // From an opening quote past the closing one: "..." and '...' on one line (escapes in the
  // basic one), """...""" and '''...''' across lines. An unclosed string runs to the end of the
  // text; the parser then reports it.
  void skip_string(char quote) {
    const bool multiline = text_.substr(at_, 3) == std::string(3, quote);
    for (int i = 0; i < (multiline ? 3 : 1); ++i) advance();
    while (at_ < text_.size()) {
      const char c = text_[at_];
      if (c == '\0') fail("a NUL byte: a config is text, and this one is damaged or not a config");
      if (quote == '"' && c == '\\' && at_ + 1 < text_.size()) {
        advance();
        advance();
        continue;
      }
      if (c == quote && (!multiline || text_.substr(at_, 3) == std::string(3, quote))) {
        for (int i = 0; i < (multiline ? 3 : 1); ++i) advance();
        return;
      }
      if (c == '\n' && !multiline) return;  // unclosed: the parser says so
      advance();
    }
  }

  std::string_view text_;
  std::string_view source_;
  std::size_t at_ = 0;
  std::size_t line_ = 1;
  std::size_t column_ = 1;
  int dots_ = 0;     // dots in the current key run
  int nesting_ = 0;  // open brackets and braces
};

}  // namespace

void check_toml_text(std::string_view text, std::string_view source) { TomlScanner(text, source).run(); }

toml::table parse_toml_text(std::string_view text, std::string_view source) {
  check_toml_text(text, source);
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}:{}: {}", source, e.source().begin.line, e.source().begin.column,
                                 e.description()));
  }
}

}  // namespace qdmeta
