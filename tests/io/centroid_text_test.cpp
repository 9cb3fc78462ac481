// cvt.centroids_file's reader: a small generated file reads back exactly; every shape, number and
// range problem is refused in one line that says where.
#include "qdmeta/io/centroid_text.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "expect_input_error.hpp"
#include "own_temp_path.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path path = test::own_temp_path("centroid_text_test_" + name);
  std::ofstream(path) << text;
  return path;
}

// Trailing spaces (as the authors' files have), tabs, CRLF, a blank line, exponents, no final newline.
TEST(CentroidText, ReadsAGeneratedFileExactly) {
  RowMatrix expected(4, 2);
  expected << 0.0f, 1.0f, 0.5f, 0.25f, 0.125f, 0.75f, 1.0f, 0.0f;
  const fs::path path = write_file("exact", "0 1 \n0.5\t0.25\r\n\n0.125   0.75\n1e0 0.0e0");
  EXPECT_TRUE(read_centroid_text(path, 4, 2) == expected);
}

TEST(CentroidText, RefusesEachProblemInOneLine) {
  const struct {
    const char* name;
    const char* text;
    const char* message;
  } cases[] = {
      {"columns", "0 1\n0.5 0.5 0.5\n", "line 2 has 3 numbers, expected 2 (the task's base features)"},
      {"few", "0 1\n\n0.5 0.5\n", "2 centroids, expected 3 (cvt.centroids)"},
      {"many", "0 1\n0 0\n1 1\n0.5 0.5\n", "more than 3 centroids (cvt.centroids); line 4 is one too many"},
      {"word", "0 1\n0.5 half\n0 0\n", "line 2: \"half\" is not a number"},
      {"nan", "0 1\nnan 0\n0 0\n", "line 2, column 1: nan is outside the base-feature space [0, 1]"},
      {"range", "0 1\n0 1.5\n0 0\n", "line 2, column 2: 1.5 is outside the base-feature space [0, 1]"},
      {"negative", "0 -0.25\n0 1\n0 0\n", "line 1, column 2: -0.25 is outside the base-feature space [0, 1]"},
  };
  for (const auto& c : cases) {
    const fs::path path = write_file(c.name, c.text);
    EXPECT_EQ(input_error_message([&] { (void)read_centroid_text(path, 3, 2); }), c.message) << c.name;
  }
  const std::string missing = input_error_message([] { (void)read_centroid_text("/nonexistent/c.dat", 3, 2); });
  EXPECT_NE(missing.find("/nonexistent/c.dat"), std::string::npos) << missing;
}

}  // namespace
}  // namespace qdmeta
