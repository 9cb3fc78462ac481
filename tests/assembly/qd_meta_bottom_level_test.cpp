// qd_meta.bottom_level from a config (assembly/builtin_algorithms.cpp): "cma-mae" reads [emitters]
// and the thresholds on [archive] as algorithm "cma-mae" does and makes a generation of
// emitters.count x emitters.batch_size rows; the keys of one bottom level are refused under the
// other in one line naming the key; the default writes nothing new into the resolved config.
#include <gtest/gtest.h>

#include <string>

#include "expect_input_error.hpp"
#include "qdmeta/algorithms/qd_meta.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {
namespace {

const std::string kHead =
    "algorithm = \"qd-meta\"\n[task]\nname = \"rastrigin\"\ndimensions = 6\n[control]\nkind = \"static\"\n"
    "generations = 2\n";

BuiltRun build(const std::string& text) { return build_run(toml::parse(text), "case.toml", {}); }

TEST(QdMetaBottomLevel, CmaMaeReadsTheEmittersAndThresholdsAndSizesAGenerationByThem) {
  const BuiltRun run = build(kHead + "[qd_meta]\nbottom_level = \"cma-mae\"\ninitial_population = 100\n"
                                     "meta_population = 2\n[emitters]\ncount = 3\nbatch_size = 7\n"
                                     "[archive]\nbins = [10, 10]\nlearning_rate = 0.5\n");
  const toml::table& r = run.resolved;
  EXPECT_EQ(r["qd_meta"]["bottom_level"].value<std::string>(), "cma-mae");
  EXPECT_FALSE(r["qd_meta"]["batch_size"]);  // the emitters size a generation
  EXPECT_FALSE(r["mutation"]);               // nothing to mutate
  EXPECT_EQ(r["emitters"]["ranker"].value<std::string>(), "improvement");  // CMA-MAE's defaults
  EXPECT_EQ(r["emitters"]["selection_rule"].value<std::string>(), "mu");
  EXPECT_EQ(r["archive"]["learning_rate"].value<double>(), 0.5);
  EXPECT_EQ(r["archive"]["threshold_min"].value<double>(), -2000.0);  // the task's QD-score offset
  SerialEvaluator evaluator;
  run.algorithm->step(evaluator);
  EXPECT_EQ(run.algorithm->counters().bottom, 100 + 2 * 2 * 3 * 7);  // seeds + maps x G x emitters x rows
  const auto& q = dynamic_cast<const QdMeta&>(*run.algorithm);
  ASSERT_NE(q.emitters(1), nullptr);
  EXPECT_EQ(q.emitters(1)->batch_size(), 21);
  EXPECT_EQ(q.emitters(1)->thresholds().params(), (ThresholdParams{0.5, -2000.0}));
  // The resolved config runs again as it is.
  EXPECT_EQ(build_run(r, "resolved.toml", {}).resolved, r);
}

TEST(QdMetaBottomLevel, TheDefaultAddsNothingToTheResolvedConfig) {
  const BuiltRun run = build(kHead);
  EXPECT_FALSE(run.resolved["qd_meta"]["bottom_level"]);
  EXPECT_FALSE(run.resolved["emitters"]);
  EXPECT_FALSE(run.resolved["archive"]["learning_rate"]);
  EXPECT_EQ(run.resolved["qd_meta"]["batch_size"].value<std::int64_t>(), 400);
  EXPECT_TRUE(run.resolved["mutation"]);
  EXPECT_EQ(dynamic_cast<const QdMeta&>(*run.algorithm).emitters(0), nullptr);
}

TEST(QdMetaBottomLevel, KeysOfTheOtherBottomLevelAreRefusedByName) {
  const std::string cma = kHead + "[qd_meta]\nbottom_level = \"cma-mae\"\n";
  const std::string why = "it is read only with qd_meta.bottom_level = \"cma-mae\"";
  const struct {
    std::string config, message;
  } cases[] = {
      {cma + "batch_size = 400\n", "qd_meta.batch_size does not apply with qd_meta.bottom_level = \"cma-mae\": a "
                                   "generation is emitters.count x emitters.batch_size rows per map"},
      {cma + "[mutation]\nsigma = 0.0025\n", "[mutation] does not apply to algorithm \"qd-meta\": with "
                                              "qd_meta.bottom_level = \"cma-mae\" its emitters make each batch"},
      {kHead + "[emitters]\ncount = 5\n", "[emitters] does not apply to algorithm \"qd-meta\": " + why},
      {kHead + "[archive]\nthreshold_min = -10\n", "archive.threshold_min does not apply to algorithm \"qd-meta\": " + why},
      {kHead + "[qd_meta]\nbottom_level = \"cma-me\"\n",
       "qd_meta.bottom_level = \"cma-me\" is not a valid choice: use one of \"map-elites\", \"cma-mae\""},
      {cma + "[emitters]\ncount = 100\nbatch_size = 100001\n",
       "emitters.count x emitters.batch_size = 10000100 is above the 10^7 rows a map's generation may have"},
      {cma + "[emitters]\nrestart_every = 5\n",
       "emitters.restart_every applies only to restart_rule = \"every-n\" (here \"basic\")"},
  };
  for (const auto& c : cases) EXPECT_INPUT_ERROR(build(c.config), "case.toml: " + c.message);
}

}  // namespace
}  // namespace qdmeta
