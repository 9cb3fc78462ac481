// `qdmeta adapt`: the test phase's curve of a finished run, the same at any thread count; an
// unknown test or an unfinished run refused.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "cli_suite.hpp"

namespace qdmeta {
namespace {

using namespace cli_suite;  // NOLINT(google-build-using-namespace): the suite's own helpers

TEST(CliAdapt, AdaptWritesTheTestPhaseCurveOfAFinishedRun) {
  const fs::path run = fresh_dir("adapt");
  ASSERT_EQ(qdmeta_cli("run --config " + config_path() + " --out " + run.string() + " --evals 20000 --quiet").status, 0);
  for (const std::string test : {"dimension", "translation"}) {
    const Outcome one = qdmeta_cli("adapt --run " + run.string() + " --test " + test + " --threads 1");
    ASSERT_EQ(one.status, 0) << one.output;
    EXPECT_NE(one.output.find("120 functions x 100 evaluations"), std::string::npos) << one.output;
    const std::string curve = slurp(run / ("adapt-" + test + ".csv"));
    ASSERT_EQ(qdmeta_cli("adapt --run " + run.string() + " --test " + test + " --threads 2 --quiet").status, 0);
    EXPECT_EQ(curve, slurp(run / ("adapt-" + test + ".csv")));  // any thread count, same bits
    std::istringstream rows(curve);
    std::string line;
    std::getline(rows, line);
    EXPECT_EQ(line, "evaluations,best_mean,best_se");
    double previous = -1e300;
    int count = 0;
    while (std::getline(rows, line)) {
      ++count;
      EXPECT_EQ(std::stoi(line), count);
      const double best = std::stod(line.substr(line.find(',') + 1));
      EXPECT_GE(best, previous);
      EXPECT_GE(best, -2000.0);  // scores are max(-M, f)
      EXPECT_LE(best, 0.0);
      previous = best;
    }
    EXPECT_EQ(count, 100);
  }
  const Outcome bad = qdmeta_cli("adapt --run " + run.string() + " --test sideways");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.output.find("valid tests are dimension, translation"), std::string::npos) << bad.output;
  fs::remove(run / "summary.json");  // as if the run had not finished
  const Outcome unfinished = qdmeta_cli("adapt --run " + run.string() + " --test dimension --budget 5");
  EXPECT_EQ(unfinished.status, 2);
  EXPECT_NE(unfinished.output.find("has not finished"), std::string::npos) << unfinished.output;
}

}  // namespace
}  // namespace qdmeta
