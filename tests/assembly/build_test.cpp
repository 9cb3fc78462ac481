// Tests of build_run in src/qdmeta/experiment/build.{hpp,cpp}: exact messages for bad input,
// defaults recorded in the resolved table, and the shipped configs.
#include "qdmeta/assembly/build.hpp"

#include "expect_input_error.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const std::string kShipped = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml";

// ---------------------------------------------------------------------------------------------
// build_run

toml::table shipped() { return load_toml(kShipped); }

TEST(BuildRun, ShippedConfigBuilds) {
  const BuiltRun run = build_run(shipped(), kShipped, {});
  ASSERT_NE(run.algorithm, nullptr);
  EXPECT_EQ(run.algorithm->name(), "map-elites");
  EXPECT_EQ(run.algorithm->generation(), 0);
  EXPECT_EQ(run.algorithm->counters(), EvaluationCounters{});
  EXPECT_EQ(run.settings.algorithm, "map-elites");
  EXPECT_EQ(run.settings.seed, 1u);
  EXPECT_EQ(run.settings.budget, 1'000'000);
  EXPECT_EQ(run.settings.counts, BudgetCount::kBottom);
  EXPECT_EQ(run.settings.log_every, 5'000);  // auto: budget / 200

  const toml::table& r = run.resolved;
  EXPECT_EQ(r["algorithm"].value<std::string>(), "map-elites");
  EXPECT_EQ(r["seed"].value<std::int64_t>(), 1);
  EXPECT_EQ(r["budget"]["evaluations"].value<std::int64_t>(), 1'000'000);
  EXPECT_EQ(r["budget"]["counts"].value<std::string>(), "bottom");
  EXPECT_EQ(r["task"]["name"].value<std::string>(), "rastrigin");
  EXPECT_EQ(r["task"]["dimensions"].value<std::int64_t>(), 20);
  EXPECT_EQ(r["task"]["score_m"].value<double>(), 2000.0);
  EXPECT_EQ(r["mutation"]["kind"].value<std::string>(), "gaussian");
  EXPECT_EQ(r["mutation"]["rate"].value<double>(), 0.10);
  EXPECT_EQ(r["mutation"]["sigma"].value<double>(), 0.05);
  EXPECT_EQ(r["mutation"]["step"].value<double>(), 0.025);  // absent from the file: default recorded
  EXPECT_EQ(r["map_elites"]["batch_size"].value<std::int64_t>(), 400);
  EXPECT_EQ(r["map_elites"]["initial_population"].value<std::int64_t>(), 2000);
  EXPECT_EQ(r["archive"]["lower"].value<double>(), 0.0);  // default recorded
  EXPECT_EQ(r["archive"]["upper"].value<double>(), 1.0);
  const toml::array* bins = r["archive"]["bins"].as_array();
  ASSERT_NE(bins, nullptr);
  ASSERT_EQ(bins->size(), 2u);
  EXPECT_EQ((*bins)[0].value<std::int64_t>(), 100);
  const toml::array* measures = r["archive"]["measures"].as_array();
  ASSERT_NE(measures, nullptr);
  ASSERT_EQ(measures->size(), 2u);
  EXPECT_EQ((*measures)[1].value<std::int64_t>(), 1);
}

TEST(BuildRun, ResolvedTableRebuildsTheSameRun) {
  const BuiltRun first = build_run(shipped(), kShipped, {});
  const BuiltRun second = build_run(first.resolved, "resolved.toml", {});
  EXPECT_EQ(second.settings.seed, first.settings.seed);
  EXPECT_EQ(second.settings.budget, first.settings.budget);
  EXPECT_EQ(second.settings.log_every, first.settings.log_every);
  EXPECT_EQ(second.resolved, first.resolved);
}

TEST(BuildRun, OverridesLandInSettingsAndResolvedTable) {
  Overrides o;
  o.seed = 7;
  o.evaluations = 5000;
  const BuiltRun run = build_run(shipped(), kShipped, o);
  EXPECT_EQ(run.settings.seed, 7u);
  EXPECT_EQ(run.settings.budget, 5000);
  EXPECT_EQ(run.resolved["seed"].value<std::int64_t>(), 7);
  EXPECT_EQ(run.resolved["budget"]["evaluations"].value<std::int64_t>(), 5000);
  EXPECT_EQ(run.resolved["budget"]["counts"].value<std::string>(), "bottom");  // the rest of [budget] kept

  // A config without a [budget] table gets one.
  toml::table no_budget = shipped();
  no_budget.erase("budget");
  const BuiltRun run2 = build_run(no_budget, "x.toml", o);
  EXPECT_EQ(run2.settings.budget, 5000);
  EXPECT_EQ(run2.resolved["budget"]["evaluations"].value<std::int64_t>(), 5000);

  // Only the seed.
  Overrides seed_only;
  seed_only.seed = 99;
  const BuiltRun run3 = build_run(shipped(), kShipped, seed_only);
  EXPECT_EQ(run3.settings.seed, 99u);
  EXPECT_EQ(run3.settings.budget, 1'000'000);
}

TEST(BuildRun, EmptyConfigUsesDefaults) {
  const BuiltRun run = build_run(toml::table{}, "empty.toml", {});
  ASSERT_NE(run.algorithm, nullptr);
  EXPECT_EQ(run.settings.algorithm, "map-elites");
  EXPECT_EQ(run.settings.seed, 1u);
  EXPECT_EQ(run.settings.budget, 1'000'000);
  EXPECT_EQ(run.settings.log_every, 5000);  // budget / 200 when [log] every = 0
  EXPECT_EQ(run.resolved["task"]["dimensions"].value<std::int64_t>(), 20);
  EXPECT_EQ(run.resolved["mutation"]["sigma"].value<double>(), 0.05);
}

TEST(BuildRun, MisspelledTaskKeyIsNamed) {
  toml::table cfg = shipped();
  cfg["task"].as_table()->insert_or_assign("dimensionz", 3);
  const std::string msg = input_error_message([&] { build_run(cfg, "bad.toml", {}); });
  EXPECT_TRUE(contains(msg, "bad.toml")) << msg;
  EXPECT_TRUE(contains(msg, "unknown key 'task.dimensionz' in [task]")) << msg;
  EXPECT_TRUE(contains(msg, "dimensions")) << msg;
}

TEST(BuildRun, MisspelledAlgorithmListsValidNames) {
  toml::table cfg = shipped();
  cfg.insert_or_assign("algorithm", "map-elite");
  const std::string msg = input_error_message([&] { build_run(cfg, "bad.toml", {}); });
  EXPECT_TRUE(msg.starts_with("bad.toml: algorithm = \"map-elite\" is not a valid choice: use one of ")) << msg;
  EXPECT_TRUE(contains(msg, "\"map-elites\"")) << msg;
}

TEST(BuildRun, ZeroBudgetFails) {
  toml::table cfg = shipped();
  cfg["budget"].as_table()->insert_or_assign("evaluations", 0);
  EXPECT_INPUT_ERROR(build_run(cfg, "bad.toml", {}),
                     "bad.toml: budget.evaluations = 0 is out of range: must be in [1, 9223372036854775807]");
  Overrides o;
  o.evaluations = 0;
  const std::string msg = input_error_message([&] { build_run(shipped(), "x.toml", o); });
  EXPECT_TRUE(contains(msg, "budget.evaluations = 0 is out of range")) << msg;
}

TEST(BuildRun, OtherBadConfigs) {
  struct Case {
    const char* toml_text;
    const char* expected;  // part of the message
  };
  const Case cases[] = {
      {"sed = 3\n", "unknown key 'sed' at the top level"},
      {"[budget]\ncounts = \"everything\"\n", "budget.counts = \"everything\" is not a valid choice: use one of \"bottom\", \"all\""},
      {"[mutation]\nrate = 1.5\n", "mutation.rate = 1.5 is out of range"},
      {"[mutation]\nkind = \"iso-line\"\nline_sigma = -0.5\n", "mutation.line_sigma = -0.5 is out of range"},
      {"[mutation]\nkind = \"iso-line\"\niso_sigma = -1\n", "mutation.iso_sigma = -1 is out of range"},
      {"[mutation]\nkind = \"iso-line\"\nsigma = 0.3\n",
       "mutation.sigma is not read by mutation kind \"iso-line\" (it reads iso_sigma, line_sigma): remove it"},
      {"[mutation]\nkind = \"gaussian\"\nstep = 0.5\n",
       "mutation.step is not read by mutation kind \"gaussian\" (it reads rate, sigma): remove it"},
      {"[archive]\nbins = [100, 0]\n", "archive.bins holds 0, out of range"},
      {"[archive]\nbins = [10, 10]\nmeasures = [0, 25]\n", "archive.measures holds 25, out of range"},
      {"[archive]\nbins = [10, 10]\nmeasures = [0]\n", "archive.measures has 1 entries"},
      {"algorithm = \"map-elites\"\n[task]\ndimensions = 2\n[archive]\nbins = [10, 10, 10]\n",
       "archive.bins has 3 entries (one per target feature), but the task has 2 base features: give at most 2, or "
       "archive.measures to pick a base feature for each"},
      {"[archive]\nlower = 1.0\nupper = 0.0\n", "lower must be below upper"},
      {"[archive]\nlower = 0.0\nupper = 1e-320\n", "archive range [0, 1e-320] is too narrow"},
      {"[task]\nname = \"rhex\"\n", "task.name = \"rhex\" is not a valid choice: use one of \"rastrigin\""},
      {"[task]\ndimensions = 0\n", "task.dimensions = 0 is out of range"},
      {"[map_elites]\nbatch_size = 0\n", "map_elites.batch_size = 0 is out of range"},
      {"seed = -1\n", "seed = -1 is out of range"},
      {"seed = \"one\"\n", "seed must be an integer, got a string"},
      {"task = 3\n", "task must be a table"},
  };
  for (const auto& c : cases) {
    const toml::table cfg = toml::parse(c.toml_text);
    const std::string msg = input_error_message([&] { build_run(cfg, "case.toml", {}); });
    EXPECT_TRUE(contains(msg, "case.toml")) << c.toml_text << " -> " << msg;
    EXPECT_TRUE(contains(msg, c.expected)) << c.toml_text << " -> " << msg;
  }
}

TEST(BuildRun, ShippedCvtConfigBuildsWithThePapersSettings) {
  const std::string path = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/cvt-map-elites.toml";
  const BuiltRun run = build_run(load_toml(path), path, {});
  ASSERT_NE(run.algorithm, nullptr);
  EXPECT_EQ(run.algorithm->name(), "cvt-map-elites");
  EXPECT_EQ(run.settings.budget, 100'000'000);
  EXPECT_EQ(run.algorithm->stats(), ArchiveStats{});  // the centroids come with the first step
  const toml::table& r = run.resolved;
  EXPECT_EQ(r["cvt"]["centroids"].value<std::int64_t>(), 10'000);
  EXPECT_EQ(r["cvt"]["samples"].value<std::int64_t>(), 1'000'000);
  EXPECT_EQ(r["cvt"]["init"].value<std::string>(), "k-means++");
  EXPECT_EQ(r["cvt"]["method"].value<std::string>(), "lloyd");
  EXPECT_EQ(r["cvt"]["batch_size"].value<std::int64_t>(), 100'000);  // default recorded
  EXPECT_EQ(r["cvt"]["lookup_chunk"].value<std::int64_t>(), 50);
  EXPECT_EQ(r["map_elites"]["batch_size"].value<std::int64_t>(), 400);
  EXPECT_EQ(r["mutation"]["sigma"].value<double>(), 0.05);
}

TEST(BuildRun, BadCvtConfigs) {
  struct Case {
    const char* toml_text;
    const char* expected;
  };
  const Case cases[] = {
      {"algorithm = \"cvt-map-elites\"\n[cvt]\ncentroids = 0\n", "cvt.centroids = 0 is out of range"},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\nsamples = 50\n", "cvt.samples = 50 is out of range: must be in [10000,"},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\nmethod = \"elkan\"\n",
       "cvt.method = \"elkan\" is not a valid choice: use one of \"lloyd\", \"mini-batch\""},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\ninit = \"kmeans++\"\n", "use one of \"k-means++\", \"random\""},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\ncentroid = 5\n", "unknown key 'cvt.centroid'"},
      {"algorithm = \"cvt-map-elites\"\n[cvt]\ncache = \"yes\"\n", "cvt.cache must be true or false, got a string"},
      {"algorithm = \"cvt-map-elites\"\n[map_elites]\nbatch_size = 0\n", "map_elites.batch_size = 0 is out of range"},
      {"algorithm = \"map-elites\"\n[cvt]\ncentroids = 5\n", "unknown key 'cvt'"},
  };
  for (const auto& c : cases) {
    const toml::table cfg = toml::parse(c.toml_text);
    const std::string msg = input_error_message([&] { build_run(cfg, "case.toml", {}); });
    EXPECT_TRUE(contains(msg, "case.toml")) << c.toml_text << " -> " << msg;
    EXPECT_TRUE(contains(msg, c.expected)) << c.toml_text << " -> " << msg;
  }
}

TEST(BuildRun, MutationStepThatDoesNotDivideOneNamesTheFile) {
  // build.hpp: "Throws InputError naming the file and key for anything wrong in the config."
  // mutation.step passes its range check but fails MutationParams::validate (0.3 does not
  // divide 1); that message must carry the file name like every other config error.
  const toml::table cfg = toml::parse("[mutation]\nkind = \"discrete-step\"\nstep = 0.3\n");
  const std::string msg = input_error_message([&] { build_run(cfg, "case.toml", {}); });
  EXPECT_TRUE(contains(msg, "mutation.step = 0.3")) << msg;
  EXPECT_TRUE(msg.starts_with("case.toml: ")) << msg;
}

// meta_fitness.dimension_count is read up to its declared 10^4 and then held to the task's N.
TEST(BuildRun, DimensionCountAboveTheGenotypeSizeNamesTheKey) {
  const auto config = [](int count) {
    return toml::parse(fmt::format("algorithm = \"qd-meta\"\n[task]\ndimensions = 4\n[meta_fitness]\n"
                                   "kind = \"dimension\"\ndimension_count = {}\n",
                                   count));
  };
  EXPECT_NO_THROW(build_run(config(4), "case.toml", {}));
  EXPECT_EQ(input_error_message([&] { build_run(config(5), "case.toml", {}); }),
            "case.toml: meta_fitness.dimension_count = 5 is out of range: must be in [1, 4]");
}

}  // namespace
}  // namespace qdmeta

namespace qdmeta {
namespace {

const std::string kAurora = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/aurora.toml";

TEST(BuildRun, ShippedAuroraConfigBuildsWithThePapersSettings) {
  const BuiltRun run = build_run(load_toml(kAurora), kAurora, {});
  EXPECT_EQ(run.settings.algorithm, "aurora");
  EXPECT_EQ(run.algorithm->name(), "aurora");
  EXPECT_EQ(run.settings.budget, 100'000'000);
  const auto& a = *run.resolved["aurora"].as_table();
  EXPECT_EQ(a["latent_size"].value<std::int64_t>(), 2);
  EXPECT_EQ(a["target_size"].value<std::int64_t>(), 10'000);
  EXPECT_EQ(a["batch_size"].value<std::int64_t>(), 400);
  EXPECT_EQ(a["initial_population"].value<std::int64_t>(), 2000);
  EXPECT_EQ(a["novelty_neighbours"].value<std::int64_t>(), 15);
  EXPECT_EQ(a["size_control_gain"].value<double>(), 5e-6);
  EXPECT_EQ(run.resolved["mutation"]["sigma"].value<double>(), 0.05);
  EXPECT_EQ(run.algorithm->stats().num_elites, 0);
}

TEST(BuildRun, BadAuroraConfigsNameTheKey) {
  struct Case {
    const char* toml_text;
    const char* expected;  // part of the message
  };
  const Case cases[] = {
      {"algorithm = \"aurora\"\n[aurora]\nlatent_sise = 2\n", "unknown key 'aurora.latent_sise' in [aurora]"},
      {"algorithm = \"aurora\"\n[aurora]\neps = 1.5\n", "aurora.eps = 1.5 is out of range"},
      {"algorithm = \"aurora\"\n[aurora]\nhidden = []\n", "aurora.hidden has 0 entries"},
      {"algorithm = \"aurora\"\n[aurora]\ntarget_size = 0\n", "aurora.target_size = 0 is out of range"},
      {"algorithm = \"aurora\"\n[archive]\nbins = [10, 10]\n", "[archive] does not apply to algorithm \"aurora\""},
  };
  for (const auto& c : cases) {
    const toml::table cfg = toml::parse(c.toml_text);
    const std::string msg = input_error_message([&] { build_run(cfg, "case.toml", {}); });
    EXPECT_TRUE(msg.starts_with("case.toml")) << c.toml_text << " -> " << msg;
    EXPECT_TRUE(contains(msg, c.expected)) << c.toml_text << " -> " << msg;
  }
}

}  // namespace
}  // namespace qdmeta
