// Byte-identity of every algorithm's results against outputs recorded from an earlier main
// (tests/data/golden/<case>/: the config, and the archive.csv, metrics.csv and meta.csv it gave).
// A refactor that changes no result leaves these files unchanged, bit for bit, on one thread and
// on two. A deliberate change of results re-records them (tests/data/golden/README.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli/cli_helpers.hpp"

namespace qdmeta::cli_test {
namespace {

namespace fs = std::filesystem;

const fs::path kGolden = fs::path(QDMETA_SOURCE_DIR) / "tests" / "data" / "golden";

struct GoldenCase {
  std::string name;
  int threads;
};

class Golden : public ::testing::TestWithParam<GoldenCase> {};

TEST_P(Golden, ResultsAreByteIdenticalToTheRecordedOnes) {
#ifdef QDMETA_SANITIZED
  GTEST_SKIP() << "the references are the Release build's bits; this Debug build does not fuse multiply-adds";
#endif
  const GoldenCase& c = GetParam();
  const fs::path reference = kGolden / c.name;
  const fs::path out = process_scratch("golden") / (c.name + "_t" + std::to_string(c.threads));
  const Outcome o = shell(std::string(QDMETA_BINARY) + " run --config '" + (reference / "config.toml").string() +
                          "' --out '" + out.string() + "' --overwrite --threads " + std::to_string(c.threads));
  ASSERT_EQ(o.status, 0) << o.output;
  int compared = 0;
  for (const char* file : {"archive.csv", "metrics.csv", "meta.csv"}) {
    if (!fs::exists(reference / file)) {
      EXPECT_FALSE(fs::exists(out / file)) << file << " is written but has no reference";
      continue;
    }
    ASSERT_TRUE(fs::exists(out / file)) << file;
    EXPECT_TRUE(slurp(reference / file) == slurp(out / file)) << c.name << ": " << file << " differs from "
                                                             << (reference / file).string();
    ++compared;
  }
  EXPECT_GE(compared, 2);
}

INSTANTIATE_TEST_SUITE_P(EveryAlgorithm, Golden,
                         ::testing::Values(GoldenCase{"map-elites", 1}, GoldenCase{"map-elites", 2},
                                           GoldenCase{"cvt-map-elites", 1}, GoldenCase{"cvt-map-elites", 2},
                                           GoldenCase{"aurora", 1}, GoldenCase{"aurora", 2},
                                           GoldenCase{"qd-meta-translation", 1}, GoldenCase{"qd-meta-translation", 2},
                                           GoldenCase{"qd-meta-dimension", 1}, GoldenCase{"qd-meta-dimension", 2}),
                         [](const auto& test_info) {
                           std::string n = test_info.param.name + "_t" + std::to_string(test_info.param.threads);
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace qdmeta::cli_test
