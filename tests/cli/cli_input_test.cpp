// What the command line accepts: the help lists what a config may name; bad input is one line
// and exit status 2.
#include <gtest/gtest.h>

#include <string>

#include "cli_suite.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliInput, TheTopLevelHelpListsWhatAConfigMayName) {
  const Outcome o = qdmeta_cli("--help");
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.output.find("algorithm: map-elites, qd-meta, cvt-map-elites, aurora, cma-me, cma-mae\n"), std::string::npos) << o.output;
  EXPECT_NE(o.output.find("  [mutation] kind: gaussian, discrete-step, uniform-resample, iso-line\n  [control] kind: "
                          "static, sarsa\n  [archive] kind: grid\n  [feature_map] kind: select\n"),
            std::string::npos)
      << o.output;
  EXPECT_NE(o.output.find("[task] name = \"rastrigin\": [meta_fitness] kind translation, dimension; adapt --test "
                          "dimension, translation"),
            std::string::npos)
      << o.output;
  // RHex is either a registered task or listed as missing from the build, never silent.
  EXPECT_TRUE(o.output.find("[task] name = \"rhex\"") != std::string::npos ||
              o.output.find("not in this build: rhex") != std::string::npos)
      << o.output;
}

TEST(CliInput, BadInputIsOneLineAndExitStatusTwo) {
  const fs::path out = fresh_dir("bad");
  const fs::path unknown_key = write_config("unknown_key", "algorithm = \"map-elites\"\n[task]\ndimensionz = 3\n");
  const fs::path wrong_type = write_config("wrong_type", "[task]\ndimensions = \"twenty\"\n");
  const fs::path out_of_range = write_config("range", "[mutation]\nrate = 1.5\n");
  const fs::path bad_choice = write_config("choice", "algorithm = \"map-elite\"\n");
  const fs::path zero_budget = write_config("zero", "[budget]\nevaluations = 0\n");
  const fs::path syntax = write_config("syntax", "[task\n");
  const struct {
    std::string args;
    std::string expected;
  } cases[] = {
      {"--config " + unknown_key.string(), "task.dimensionz"},
      {"--config " + wrong_type.string(), "task.dimensions must be an integer"},
      {"--config " + out_of_range.string(), "mutation.rate = 1.5"},
      {"--config " + bad_choice.string(), "\"map-elites\""},
      {"--config " + zero_budget.string(), "budget.evaluations = 0"},
      {"--config " + syntax.string(), syntax.string() + ":1:"},
      {"--config /nonexistent/qdmeta.toml", "/nonexistent/qdmeta.toml does not exist"},
      {"--config " + config_path() + " --evals 0", "--evals"},
  };
  for (const auto& c : cases) {
    const Outcome o = qdmeta_cli("run " + c.args + " --out " + out.string());
    EXPECT_EQ(o.status, 2) << c.args << "\n" << o.output;
    EXPECT_NE(o.output.find(c.expected), std::string::npos) << c.args << "\n" << o.output;
    EXPECT_EQ(count_lines(o.output), 1) << c.args << "\n" << o.output;
    EXPECT_FALSE(fs::exists(out / "metrics.csv")) << c.args;
  }
}

TEST(CliInput, MissingSubcommandOrOptionIsAnError) {
  EXPECT_EQ(qdmeta_cli("").status, 2);
  EXPECT_EQ(qdmeta_cli("run --out /tmp/x").status, 2);
  EXPECT_EQ(qdmeta_cli("--version").status, 0);
}

}  // namespace
}  // namespace qdmeta
