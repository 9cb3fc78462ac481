// Tests of src/qdmeta/plugin/toml_text.{hpp,cpp}: what toml++ alone would read wrongly
// (a NUL byte) or crash on (keys and headers nested 100,000 deep) is refused with one line naming
// source, line and column; everything a config legitimately holds passes.
#include <gtest/gtest.h>

#include <string>

#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/toml_text.hpp"

namespace qdmeta {
namespace {

std::string refusal(const std::string& text) {
  try {
    parse_toml_text(text, "c.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string dotted(int parts, const std::string& joint = ".") {
  std::string key = "a";
  for (int i = 1; i < parts; ++i) key += joint + "a";
  return key;
}

// open + inside + close, appended in place (GCC 12 warns, wrongly, of overlapping copies in
// "literal" + string at -O3).
std::string wrapped(const std::string& open, const std::string& inside, const std::string& close) {
  std::string s = open;
  s += inside;
  s += close;
  return s;
}

TEST(TomlText, ANulByteIsRefusedNamingWhereItIs) {
  const std::string text = std::string("seed = 1\nalgorithm = \"qd") + '\0' + "-meta\"\n";
  EXPECT_EQ(refusal(text), "c.toml:2:16: a NUL byte: a config is text, and this one is damaged or not a config");
  EXPECT_NE(refusal(std::string("# a comment ") + '\0' + "\n").find("c.toml:1:13: a NUL byte"), std::string::npos);
  EXPECT_NE(refusal(std::string("seed = 1\n") + '\0').find("c.toml:2:1"), std::string::npos);
}

TEST(TomlText, KeysAndHeadersOfMoreThanTheBoundAreRefused) {
  EXPECT_EQ(refusal(wrapped("[", dotted(kMaxKeyParts), "]\nx = 1\n")), "");
  EXPECT_EQ(refusal(dotted(kMaxKeyParts) + " = 1\n"), "");
  EXPECT_EQ(refusal(wrapped("[", dotted(kMaxKeyParts + 1), "]\n")), "c.toml:1:65: a key or table header of more than 32 parts");
  EXPECT_NE(refusal(wrapped("[[", dotted(kMaxKeyParts + 1, " . "), "]]\n")).find("more than 32 parts"), std::string::npos);
  EXPECT_NE(refusal(dotted(kMaxKeyParts + 1, ".\"a\".") + " = 1\n").find("more than 32 parts"), std::string::npos);
  // The inputs that crashed the parser: 100,000 parts.
  EXPECT_NE(refusal(wrapped("[", dotted(100'000), "]\n")).find("more than 32 parts"), std::string::npos);
  EXPECT_NE(refusal(wrapped("x = 1\n", dotted(100'000), " = 1\n")).find("c.toml:2:"), std::string::npos);
}

TEST(TomlText, ValuesNestedDeeperThanTheBoundAreRefused) {
  const auto arrays = [](int depth) { return "x = " + std::string(depth, '[') + std::string(depth, ']') + "\n"; };
  EXPECT_EQ(refusal(arrays(kMaxValueNesting)), "");
  EXPECT_NE(refusal(arrays(kMaxValueNesting + 1)).find("nested more than 32 deep"), std::string::npos);
  EXPECT_NE(refusal(arrays(100'000)).find("nested more than 32 deep"), std::string::npos);
  std::string tables = "x = ";
  for (int i = 0; i < 100'000; ++i) tables += "{a=";
  EXPECT_NE(refusal(tables + "1").find("nested more than 32 deep"), std::string::npos);
}

TEST(TomlText, DotsInStringsCommentsAndNumbersAreNotKeyParts) {
  const std::string many_dots(200, '.');
  const std::string text = "a = \"" + many_dots + "\"\nb = '" + many_dots + "'\n# " + many_dots +
                           "\nc = \"\"\"\n" + many_dots + "\n\"\"\"\nd = '''" + many_dots + "'''\ne = \"\\\"" +
                           many_dots + "\"\nf = [" + std::string(100, '1') + ".5, 2.5, 3.5, 4.5, 5.5]\ng = 1979-05-27T07:32:00.999\n"
                           "[\"x.y.z\".w]\nh = 1\n";
  EXPECT_EQ(refusal(text), "");
  const toml::table t = parse_toml_text(text, "c.toml");
  EXPECT_EQ(t["a"].value<std::string>(), many_dots);
  EXPECT_EQ(t["x.y.z"]["w"]["h"].value<std::int64_t>(), 1);
}

TEST(TomlText, ASyntaxErrorNamesSourceLineAndColumn) {
  EXPECT_NE(refusal("seed = 1\nx = = 2\n").find("c.toml:2:"), std::string::npos);
}

}  // namespace
}  // namespace qdmeta
