// [[claim]] tables: the cases tools/claim_rules.py is tested on too (tests/data/claims/cases.toml),
// judged alike, and every committed experiment file's claims accepted.
#include "qdmeta/experiment/claim_rules.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "qdmeta/core/error.hpp"
#include "qdmeta/experiment/experiment.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> strings(const toml::node_view<const toml::node>& list) {
  std::vector<std::string> out;
  for (const toml::node& s : *list.as_array()) out.push_back(s.value<std::string>().value());
  return out;
}

TEST(ClaimRules, EverySharedCaseIsJudgedAsItsFileSays) {
  const fs::path file = fs::path(QDMETA_SOURCE_DIR) / "tests/data/claims/cases.toml";
  const toml::table cases = toml::parse_file(file.string());
  const std::vector<std::string> conditions = strings(cases["conditions"]), tests = strings(cases["tests"]);
  int accepted = 0, refused = 0;
  for (const toml::node& node : *cases["case"].as_array()) {
    const toml::table& c = *node.as_table();
    const std::string error = c["error"].value<std::string>().value();
    toml::array claims;
    claims.push_back(*c["claim"].as_table());
    try {
      check_claims(claims, conditions, tests, "cases.toml");
      EXPECT_EQ(error, "") << "accepted, but the case says: " << error;
      ++accepted;
    } catch (const InputError& e) {
      EXPECT_NE(error, "") << "refused an accepted case: " << e.what();
      EXPECT_NE(std::string(e.what()).find(error), std::string::npos) << e.what() << "\nshould hold: " << error;
      EXPECT_TRUE(std::string(e.what()).starts_with("cases.toml:")) << e.what();
      ++refused;
    }
  }
  EXPECT_EQ(accepted, 8);  // every kind, "near" and "below" with and without their options
  EXPECT_GE(refused, 30);
}

TEST(ClaimRules, EveryCommittedExperimentFilesClaimsAreAccepted) {
  std::size_t claims = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(QDMETA_SOURCE_DIR) / "configs")) {
    if (entry.path().extension() != ".toml") continue;
    std::stringstream text;
    text << std::ifstream(entry.path()).rdbuf();
    if (text.str().find("[[condition]]") == std::string::npos) continue;  // a run config
    const ExperimentSpec spec = load_experiment(entry.path(), std::nullopt, std::nullopt);
    claims += spec.claims.size();
  }
  EXPECT_GE(claims, 30u);  // 37 now: the check must not pass by finding none
}

}  // namespace
}  // namespace qdmeta
