// Tests of src/qdmeta/experiment/config_fingerprint.{hpp,cpp}: what the resolved config
// fingerprint covers, and the keys a refusal names.
#include "qdmeta/assembly/config_fingerprint.hpp"

#include <gtest/gtest.h>

#include <string>

#include "qdmeta/assembly/build.hpp"

namespace qdmeta {
namespace {

toml::table resolved(const std::string& text) {
  return build_run(toml::parse(text), "test.toml", {}, BuildScope::kTasksOnly).resolved;
}

TEST(ConfigFingerprint, IgnoresWhatDiffersBetweenReplicatesAndChangesNoResult) {
  const std::string base = "algorithm = \"cvt-map-elites\"\n[cvt]\ncentroids = 50\n";
  const std::string f = resolved_config_fingerprint(resolved(base));
  EXPECT_TRUE(is_config_fingerprint(f)) << f;
  EXPECT_EQ(resolved_config_fingerprint(resolved("seed = 7\n" + base)), f);
  EXPECT_EQ(resolved_config_fingerprint(resolved(base + "cache = false\ncache_dir = \"/tmp/x\"\n[checkpoint]\n"
                                                        "every_seconds = 5\n")),
            f);
  toml::table with_provenance = resolved(base);
  with_provenance.insert("provenance", toml::table{{"threads", 8}, {"qdmeta_version", "9.9.9"}});
  EXPECT_EQ(resolved_config_fingerprint(with_provenance), f);
}

TEST(ConfigFingerprint, ChangesWithAnyKeyOfTheRunAndNamesIt) {
  const toml::table a = resolved("algorithm = \"map-elites\"\n[mutation]\nsigma = 0.05\n");
  const toml::table b = resolved("algorithm = \"map-elites\"\n[mutation]\nsigma = 0.2\n");
  const toml::table c = resolved("algorithm = \"map-elites\"\n[mutation]\nsigma = 0.2\n[budget]\nevaluations = 5\n");
  EXPECT_NE(resolved_config_fingerprint(a), resolved_config_fingerprint(b));
  EXPECT_EQ(differing_keys(a, b), std::vector<std::string>{"mutation.sigma"});
  EXPECT_EQ(keys_that_differ(differing_keys(a, b)), "mutation.sigma differs");
  EXPECT_EQ(keys_that_differ(differing_keys(a, c)), "budget.evaluations, mutation.sigma differ");
  EXPECT_EQ(differing_keys(a, resolved("seed = 3\nalgorithm = \"map-elites\"\n[mutation]\nsigma = 0.05\n")),
            std::vector<std::string>{});
  const toml::table plain = toml::parse("x = 1\n");
  EXPECT_EQ(differing_keys(plain, toml::parse("x = 1\n[extra]\ny = 2\n")), std::vector<std::string>{"extra"});
  EXPECT_EQ(keys_that_differ({"a", "b", "c", "d", "e", "f", "g", "h"}), "a, b, c, d, e, f and 2 more differ");
}

TEST(ConfigFingerprint, HasTheFormOfSixteenLowercaseHexDigits) {
  EXPECT_TRUE(is_config_fingerprint("0123456789abcdef"));
  EXPECT_FALSE(is_config_fingerprint("0123456789ABCDEF"));
  EXPECT_FALSE(is_config_fingerprint("0123456789abcde"));
  EXPECT_FALSE(is_config_fingerprint(""));
}

}  // namespace
}  // namespace qdmeta
