// Tests of src/qdmeta/experiment/config.{hpp,cpp} (ConfigReader over toml++ tables, load_toml)
// and of build_run in src/qdmeta/experiment/build.{hpp,cpp}: exact messages for bad input
// (after fmt's EXPECT_THROW_MSG), defaults recorded in the resolved table, and the shipped config.
#include "expect_input_error.hpp"
#include "qdmeta/experiment/config.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/experiment/build.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

std::string input_error(auto&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError)";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

const std::string kShipped = std::string(QDMETA_SOURCE_DIR) + "/configs/rastrigin/map-elites.toml";

class ConfigFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("qdmeta_config_test_") + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& content) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << content;
    return p;
  }
  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// ConfigReader

TEST(ConfigReader, ReadsGivenValues) {
  const toml::table t = toml::parse(R"(
    count = 7
    ratio = 0.25
    whole = 3
    flag = true
    word = "hello"
    list = [1, 2, 3]
  )");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  EXPECT_EQ(r.integer("count", 0, 0, 10), 7);
  EXPECT_EQ(r.number("ratio", 0.0, 0.0, 1.0), 0.25);
  EXPECT_EQ(r.number("whole", 0.0, 0.0, 10.0), 3.0);  // integers are numbers
  EXPECT_TRUE(r.boolean("flag", false));
  EXPECT_EQ(r.string("word", "x"), "hello");
  EXPECT_EQ(r.integers("list", {}, 0, 10, 1, 5), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_TRUE(r.has("count"));
  EXPECT_FALSE(r.has("missing"));
  EXPECT_EQ(r.source(), "test.toml");
  EXPECT_NO_THROW(r.finish());
}

TEST(ConfigReader, UnknownKeyNamesItAndListsValidKeys) {
  const toml::table t = toml::parse("alpha = 1\nbeta = 2.5\nbogus = 3\n");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  r.integer("alpha", 0, 0, 10);
  r.number("beta", 0, 0, 10);
  r.boolean("gamma", false);  // absent but valid: listed too
  EXPECT_INPUT_ERROR(r.finish(), "test.toml: unknown key 'bogus' at the top level (valid keys: alpha, beta, gamma)");
}

TEST(ConfigReader, UnknownKeyInASubTable) {
  const toml::table t = toml::parse("[task]\nname = \"rastrigin\"\ndimensionz = 3\n");
  toml::table resolved;
  ConfigReader root(t, "cfg.toml", resolved);
  ConfigReader task = root.table("task");
  task.string("name", "rastrigin");
  task.integer("dimensions", 20, 1, 100);
  EXPECT_INPUT_ERROR(task.finish(),
                     "cfg.toml: unknown key 'task.dimensionz' in [task] (valid keys: dimensions, name)");
  EXPECT_NO_THROW(root.finish());  // the root read "task"

  const toml::table empty_reads = toml::parse("oops = 1\n");
  toml::table resolved2;
  ConfigReader r(empty_reads, "cfg.toml", resolved2);
  EXPECT_INPUT_ERROR(r.finish(), "cfg.toml: unknown key 'oops' at the top level (valid keys: none)");
}

TEST(ConfigReader, WrongTypeMessages) {
  const toml::table t = toml::parse(R"(
    s = "text"
    i = 3
    f = 1.5
    b = true
    a = [1, 2]
    [sub]
    x = 1
  )");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  EXPECT_INPUT_ERROR(r.integer("s", 0, 0, 10), "test.toml: s must be an integer, got a string");
  EXPECT_INPUT_ERROR(r.integer("f", 0, 0, 10), "test.toml: f must be an integer, got a floating-point");
  EXPECT_INPUT_ERROR(r.number("s", 0, 0, 10), "test.toml: s must be a number, got a string");
  EXPECT_INPUT_ERROR(r.number("b", 0, 0, 10), "test.toml: b must be a number, got a boolean");
  EXPECT_INPUT_ERROR(r.boolean("s", false), "test.toml: s must be true or false, got a string");
  EXPECT_INPUT_ERROR(r.string("b", ""), "test.toml: b must be a string, got a boolean");
  EXPECT_INPUT_ERROR(r.integers("s", {}, 0, 10, 0, 5), "test.toml: s must be an array of integers, got a string");
  EXPECT_INPUT_ERROR(r.table("s"), "test.toml: s must be a table, got a string");
  EXPECT_INPUT_ERROR(r.string("sub", ""), "test.toml: sub must be a string, got a table");

  // In a sub-table the key is qualified.
  ConfigReader sub = r.table("sub");
  EXPECT_INPUT_ERROR(sub.string("x", ""), "test.toml: sub.x must be a string, got a integer");
}

TEST(ConfigReader, OutOfRangeMessages) {
  const toml::table t = toml::parse("n = 11\nx = 2.5\nneg = -1\n[task]\ndimensions = 0\n");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  EXPECT_INPUT_ERROR(r.integer("n", 1, 1, 10), "test.toml: n = 11 is out of range: must be in [1, 10]");
  EXPECT_INPUT_ERROR(r.integer("neg", 1, 0, 10), "test.toml: neg = -1 is out of range: must be in [0, 10]");
  EXPECT_INPUT_ERROR(r.number("x", 0.5, 0.0, 1.0), "test.toml: x = 2.5 is out of range: must be in [0, 1]");
  ConfigReader task = r.table("task");
  EXPECT_INPUT_ERROR(task.integer("dimensions", 20, 1, 10000),
                     "test.toml: task.dimensions = 0 is out of range: must be in [1, 10000]");
  // Bounds are inclusive.
  const toml::table edges = toml::parse("lo = 1\nhi = 10\nf = 1.0\n");
  toml::table resolved2;
  ConfigReader e(edges, "e.toml", resolved2);
  EXPECT_EQ(e.integer("lo", 5, 1, 10), 1);
  EXPECT_EQ(e.integer("hi", 5, 1, 10), 10);
  EXPECT_EQ(e.number("f", 0.5, 0.0, 1.0), 1.0);
}

TEST(ConfigReader, IntegersListChecks) {
  const toml::table t = toml::parse(R"(
    three = [10, 20, 30]
    empty = []
    bad = [1, 200]
    mixed = [1, "two"]
  )");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  EXPECT_INPUT_ERROR(r.integers("three", {}, 1, 100, 1, 2), "test.toml: three has 3 entries: must have between 1 and 2");
  EXPECT_INPUT_ERROR(r.integers("empty", {}, 1, 100, 1, 2), "test.toml: empty has 0 entries: must have between 1 and 2");
  EXPECT_INPUT_ERROR(r.integers("bad", {}, 1, 100, 1, 2), "test.toml: bad holds 200, out of range: each must be in [1, 100]");
  const std::string mixed = input_error([&] { r.integers("mixed", {}, 1, 100, 1, 2); });
  EXPECT_TRUE(contains(mixed, "test.toml: mixed must be an array of integers")) << mixed;
  EXPECT_EQ(r.integers("three", {}, 1, 100, 3, 3), (std::vector<std::int64_t>{10, 20, 30}));
  // The fallback is checked as well.
  EXPECT_INPUT_ERROR(r.integers("absent", {1, 2, 3}, 1, 100, 1, 2),
                     "test.toml: absent has 3 entries: must have between 1 and 2");
}

TEST(ConfigReader, ChoiceListsValidValues) {
  const toml::table t = toml::parse("[mutation]\nkind = \"gauss\"\n[other]\nkind = \"discrete-step\"\n");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  ConfigReader m = r.table("mutation");
  EXPECT_INPUT_ERROR(m.choice("kind", MutationKind::kGaussian, kMutationKindNames),
                     "test.toml: mutation.kind = \"gauss\" is not a valid choice: use one of \"gaussian\", "
                     "\"discrete-step\", \"uniform-resample\"");
  ConfigReader o = r.table("other");
  EXPECT_EQ(o.choice("kind", MutationKind::kGaussian, kMutationKindNames), MutationKind::kDiscreteStep);
  EXPECT_EQ(resolved["other"]["kind"].value<std::string>(), "discrete-step");
  // Absent: the fallback, recorded by name.
  EXPECT_EQ(o.choice("absent", MutationKind::kUniformResample, kMutationKindNames), MutationKind::kUniformResample);
  EXPECT_EQ(resolved["other"]["absent"].value<std::string>(), "uniform-resample");
}

TEST(ConfigReader, DefaultsAreRecordedInTheResolvedTable) {
  const toml::table t = toml::parse("given = 4\nwhole = 2\n[task]\nname = \"x\"\n");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  r.integer("given", 1, 0, 10);
  r.integer("int_default", 9, 0, 10);
  r.number("whole", 0.5, 0.0, 10.0);
  r.number("num_default", 0.125, 0.0, 1.0);
  r.boolean("bool_default", true);
  r.string("str_default", "abc");
  r.integers("list_default", {3, 4}, 0, 10, 0, 5);
  ConfigReader task = r.table("task");
  task.string("name", "y");
  task.integer("dimensions", 20, 1, 100);
  ConfigReader absent = r.table("absent_table");
  absent.number("rate", 0.1, 0.0, 1.0);

  EXPECT_EQ(resolved["given"].value<std::int64_t>(), 4);
  EXPECT_EQ(resolved["int_default"].value<std::int64_t>(), 9);
  ASSERT_TRUE(resolved["whole"].is_floating_point());  // a number is recorded as a float
  EXPECT_EQ(resolved["whole"].value<double>(), 2.0);
  EXPECT_EQ(resolved["num_default"].value<double>(), 0.125);
  EXPECT_EQ(resolved["bool_default"].value<bool>(), true);
  EXPECT_EQ(resolved["str_default"].value<std::string>(), "abc");
  const toml::array* list = resolved["list_default"].as_array();
  ASSERT_NE(list, nullptr);
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[1].value<std::int64_t>(), 4);
  EXPECT_EQ(resolved["task"]["name"].value<std::string>(), "x");
  EXPECT_EQ(resolved["task"]["dimensions"].value<std::int64_t>(), 20);
  ASSERT_TRUE(resolved["absent_table"].is_table());
  EXPECT_EQ(resolved["absent_table"]["rate"].value<double>(), 0.1);
  // Nothing that was not read.
  EXPECT_EQ(resolved.size(), 9u);
}

TEST_F(ConfigFile, LoadTomlMissingFile) {
  const fs::path missing = dir_ / "nope.toml";
  const std::string msg = input_error([&] { load_toml(missing); });
  EXPECT_EQ(msg, "config file " + missing.string() + " does not exist");
}

TEST_F(ConfigFile, LoadTomlSyntaxErrorNamesFileAndLine) {
  const fs::path p = write("broken.toml", "a = 1\n\nb = = 2\n");
  const std::string msg = input_error([&] { load_toml(p); });
  EXPECT_TRUE(msg.starts_with(p.string() + ":3:")) << msg;
  const fs::path ok = write("ok.toml", "a = 1\n[t]\nb = \"x\"\n");
  const toml::table t = load_toml(ok);
  EXPECT_EQ(t["a"].value<std::int64_t>(), 1);
  EXPECT_EQ(t["t"]["b"].value<std::string>(), "x");
}

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
  const std::string msg = input_error([&] { build_run(cfg, "bad.toml", {}); });
  EXPECT_TRUE(contains(msg, "bad.toml")) << msg;
  EXPECT_TRUE(contains(msg, "unknown key 'task.dimensionz' in [task]")) << msg;
  EXPECT_TRUE(contains(msg, "dimensions")) << msg;
}

TEST(BuildRun, MisspelledAlgorithmListsValidNames) {
  toml::table cfg = shipped();
  cfg.insert_or_assign("algorithm", "map-elite");
  const std::string msg = input_error([&] { build_run(cfg, "bad.toml", {}); });
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
  const std::string msg = input_error([&] { build_run(shipped(), "x.toml", o); });
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
    const std::string msg = input_error([&] { build_run(cfg, "case.toml", {}); });
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
    const std::string msg = input_error([&] { build_run(cfg, "case.toml", {}); });
    EXPECT_TRUE(contains(msg, "case.toml")) << c.toml_text << " -> " << msg;
    EXPECT_TRUE(contains(msg, c.expected)) << c.toml_text << " -> " << msg;
  }
}

TEST(BuildRun, MutationStepThatDoesNotDivideOneNamesTheFile) {
  // build.hpp: "Throws InputError naming the file and key for anything wrong in the config."
  // mutation.step passes its range check but fails MutationParams::validate (0.3 does not
  // divide 1); that message must carry the file name like every other config error.
  const toml::table cfg = toml::parse("[mutation]\nkind = \"discrete-step\"\nstep = 0.3\n");
  const std::string msg = input_error([&] { build_run(cfg, "case.toml", {}); });
  EXPECT_TRUE(contains(msg, "mutation.step = 0.3")) << msg;
  EXPECT_TRUE(msg.starts_with("case.toml: ")) << msg;
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
      {"algorithm = \"aurora\"\n[archive]\nbins = [10, 10]\n", "unknown key 'archive' at the top level"},
  };
  for (const auto& c : cases) {
    const toml::table cfg = toml::parse(c.toml_text);
    const std::string msg = input_error([&] { build_run(cfg, "case.toml", {}); });
    EXPECT_TRUE(msg.starts_with("case.toml")) << c.toml_text << " -> " << msg;
    EXPECT_TRUE(contains(msg, c.expected)) << c.toml_text << " -> " << msg;
  }
}

}  // namespace
}  // namespace qdmeta
