// The config fuzzer in the suite: a few thousand cases (bench/fuzz/config_fuzz runs more).
#include <gtest/gtest.h>

#include "config_fuzzer.hpp"

namespace qdmeta::fuzz {
namespace {

TEST(ConfigFuzz, MutatedConfigsAreBuiltOrRefusedWithAMessageNeverCrashOrHang) {
  const auto seeds = seed_configs(std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin");
  ASSERT_GE(seeds.size(), 7u);
  const FuzzReport r = fuzz_configs(seeds, 1, 3000);
  EXPECT_EQ(r.cases, 3000);
  for (const std::string& d : r.defects) ADD_FAILURE() << d;
  EXPECT_TRUE(r.defects.empty());
  // The mutations must exercise both outcomes, or the fuzzer tests nothing.
  EXPECT_GT(r.accepted, 300) << r.refused << " refused";
  EXPECT_GT(r.refused, 300) << r.accepted << " accepted";
  EXPECT_GT(r.built_algorithms, 100);
  EXPECT_LT(r.slowest_seconds, 5.0) << r.slowest_case;
}

}  // namespace
}  // namespace qdmeta::fuzz
