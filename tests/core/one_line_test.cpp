// Tests of src/qdmeta/core/one_line.{hpp,cpp}: any message becomes one line of bounded length.
#include "qdmeta/core/one_line.hpp"

#include <gtest/gtest.h>

#include <string>

namespace qdmeta {
namespace {

TEST(OneLine, PlainTextIsUnchanged) {
  EXPECT_EQ(one_line("config.toml: mutation.sigma = 2 is out of range"), "config.toml: mutation.sigma = 2 is out of range");
  EXPECT_EQ(one_line("répertoire ünïcode"), "répertoire ünïcode");
}

TEST(OneLine, ControlCharactersAreEscaped) {
  EXPECT_EQ(one_line("a\nb\r\nc\td"), "a\\nb\\r\\nc\\td");
  EXPECT_EQ(one_line(std::string("nul\0esc\x1b[2Jdel\x7f", 15)), "nul\\x00esc\\x1b[2Jdel\\x7f");
}

TEST(OneLine, ALongMessageKeepsItsStartAndEndWithinTheBound) {
  const std::string value(50'000'000, 'x');
  const std::string line = one_line("key = '" + value + "' is wrong: fix it", 1000);
  EXPECT_LE(line.size(), 1000u);
  EXPECT_TRUE(line.starts_with("key = 'xxx")) << line.substr(0, 40);
  EXPECT_TRUE(line.ends_with("xxx' is wrong: fix it")) << line.substr(line.size() - 40);
  EXPECT_NE(line.find("x...x"), std::string::npos);
  EXPECT_EQ(one_line(std::string(kMaxMessageBytes, 'y')).size(), kMaxMessageBytes);  // at the bound: whole
  EXPECT_LE(one_line(std::string(kMaxMessageBytes + 1, 'y')).size(), kMaxMessageBytes);
}

TEST(OneLine, EscapesCountTowardsTheBoundAndNoCharacterIsCutInTwo) {
  EXPECT_LE(one_line(std::string(10'000, '\n'), 100).size(), 100u);
  const std::string line = one_line(std::string(3000, 'a') + std::string(1000, '\0') + "\xc3\xa9\xc3\xa9\xc3\xa9", 101);
  EXPECT_LE(line.size(), 101u);
  std::string accents;
  for (int i = 0; i < 500; ++i) accents += "\xc3\xa9";  // 'é', two bytes each
  const std::string cut = one_line(accents, 100);
  EXPECT_LE(cut.size(), 100u);
  const std::size_t dots = cut.find("...");
  ASSERT_NE(dots, std::string::npos);
  EXPECT_EQ(dots % 2, 0u);                        // the start ends on a whole character
  EXPECT_EQ((cut.size() - dots - 3) % 2, 0u);     // and so does the end
}

}  // namespace
}  // namespace qdmeta
