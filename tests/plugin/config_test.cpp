// Tests of src/qdmeta/plugin/config.{hpp,cpp} (ConfigReader over toml++ tables, load_toml):
// exact messages for bad input (after fmt's EXPECT_THROW_MSG) and defaults recorded in the
// resolved table. build_run over whole configs: tests/assembly/build_test.cpp.
#include "expect_input_error.hpp"
#include "qdmeta/plugin/config.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/mutation.hpp"

namespace qdmeta {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }


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
  // The root checks the tables opened through it: a table nobody finished is still checked.
  EXPECT_INPUT_ERROR(root.finish(),
                     "cfg.toml: unknown key 'task.dimensionz' in [task] (valid keys: dimensions, name)");

  const toml::table empty_reads = toml::parse("oops = 1\n");
  toml::table resolved2;
  ConfigReader r(empty_reads, "cfg.toml", resolved2);
  EXPECT_INPUT_ERROR(r.finish(), "cfg.toml: unknown key 'oops' at the top level (valid keys: none)");
}

// finish() on the root reaches every table opened through it, however deep, in the order they
// were opened, and counts a key read through any copy of a table's reader.
TEST(ConfigReader, FinishOnTheRootChecksEveryOpenedTable) {
  const toml::table t = toml::parse("[a]\nx = 1\n[a.b]\ny = 2\nz = 3\n[c]\nw = 4\n");
  toml::table resolved;
  ConfigReader root(t, "cfg.toml", resolved);
  ConfigReader a = root.table("a");
  a.integer("x", 0, 0, 9);
  ConfigReader b = a.table("b");
  ConfigReader b_copy = b;
  b_copy.integer("y", 0, 0, 9);
  ConfigReader c = root.table("c");
  EXPECT_NO_THROW(a.integer("x", 0, 0, 9));
  EXPECT_INPUT_ERROR(root.finish(), "cfg.toml: unknown key 'a.b.z' in [a.b] (valid keys: y)");
  b.integer("z", 0, 0, 9);
  EXPECT_INPUT_ERROR(root.finish(), "cfg.toml: unknown key 'c.w' in [c] (valid keys: none)");
  c.integer("w", 0, 0, 9);
  EXPECT_NO_THROW(root.finish());
  EXPECT_NO_THROW(b.finish());
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

// A parameter declared once is read with its own range and recorded with its meaning; read from
// a table it does not belong to, it is a programming error, not a config's.
TEST(ConfigReader, ReadsADeclaredParameterFromItsOwnTableOnly) {
  constexpr IntParam kCount{"job", "count", 1, 10, "how many"};
  constexpr RealParam kShare{"job", "share", 0.0, 1.0, Open::kLower, "what share"};
  const toml::table t = toml::parse("[job]\ncount = 11\nshare = 0.5\n");
  toml::table resolved;
  ConfigReader r(t, "test.toml", resolved);
  ConfigReader job = r.table("job");
  std::vector<ConfigKeyRecord> log;
  {
    const ScopedConfigKeyLog recording(log);
    EXPECT_INPUT_ERROR(job.integer(kCount, 3), "test.toml: job.count = 11 is out of range: must be in [1, 10]");
    EXPECT_EQ(job.number(kShare, 1.0), 0.5);
  }
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].key, "job.count");
  EXPECT_EQ(log[0].range, "1 to 10");
  EXPECT_EQ(log[0].doc, "how many");
  EXPECT_EQ(log[1].range, "(0, 1]");
  EXPECT_EQ(log[1].doc, "what share");
  // A parameter of [job] read from the root: the library's own Error (a programming error), not
  // an InputError blaming the config.
  try {
    r.integer(kCount, 3);
    ADD_FAILURE() << "a parameter read from another table was accepted";
  } catch (const InputError&) {
    ADD_FAILURE() << "reported as the config's fault";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("programming error"), std::string::npos) << e.what();
  }
  EXPECT_INPUT_ERROR(require(kShare, 0.0), "job.share = 0 is out of range: must be in (0, 1]");
  EXPECT_INPUT_ERROR(require(kCount, std::size_t{11}), "job.count = 11 is out of range: must be in [1, 10]");
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
  const std::string mixed = input_error_message([&] { r.integers("mixed", {}, 1, 100, 1, 2); });
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
                     "\"discrete-step\", \"uniform-resample\", \"iso-line\"");
  ConfigReader o = r.table("other");
  EXPECT_EQ(o.choice("kind", MutationKind::kGaussian, kMutationKindNames), MutationKind::kDiscreteStep);
  EXPECT_EQ(resolved["other"]["kind"].value<std::string>(), "discrete-step");
  // Absent: the fallback, recorded by name.
  EXPECT_EQ(o.choice("absent", MutationKind::kUniformResample, kMutationKindNames), MutationKind::kUniformResample);
  EXPECT_EQ(resolved["other"]["absent"].value<std::string>(), "uniform-resample");
}

// What an experiment file needs besides a run config's keys: lists of strings, arrays of tables
// (each checked for unknown keys, named by its place), optional integers and tables taken whole.
TEST(ConfigReader, StringListsArraysOfTablesAndOptionalValues) {
  const toml::table t = toml::parse(
      "tests = [\"a\", \"b\"]\nbad = [\"a\", 1]\ncount = 3\nwhole = { x = 1, y = [2] }\n"
      "[[item]]\nname = \"one\"\n[[item]]\nname = \"two\"\nextra = 1\n[[claim]]\nfree = 1\n");
  toml::table resolved;
  ConfigReader r(t, "e.toml", resolved);
  EXPECT_EQ(r.strings("tests", {}), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.strings("absent", {"z"}), (std::vector<std::string>{"z"}));
  EXPECT_INPUT_ERROR(r.strings("bad", {}), "e.toml: bad must be an array of strings, got a array");
  EXPECT_EQ(r.optional_integer("count", 1, 10), std::optional<std::int64_t>(3));
  EXPECT_EQ(r.optional_integer("none", 1, 10), std::nullopt);
  EXPECT_INPUT_ERROR(r.optional_integer("count", 5, 10), "e.toml: count = 3 is out of range: must be in [5, 10]");
  const toml::table* whole = r.raw_table("whole");
  ASSERT_NE(whole, nullptr);
  EXPECT_EQ(*whole, *t["whole"].as_table());
  EXPECT_EQ(r.raw_table("nowhere"), nullptr);
  EXPECT_INPUT_ERROR(r.raw_table("count"), "e.toml: count must be a table, got a integer");
  ASSERT_NE(r.raw_tables("claim"), nullptr);
  EXPECT_INPUT_ERROR(r.raw_tables("tests"), "e.toml: tests must be an array of tables ([[tests]]), got a array");
  std::vector<ConfigReader> items = r.tables("item");
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[0].string("name", ""), "one");
  EXPECT_EQ(items[1].string("name", ""), "two");
  EXPECT_TRUE(r.tables("absent_items").empty());
  // Each table's unknown keys are refused by the root's finish(), naming its place.
  EXPECT_INPUT_ERROR(r.finish(), "e.toml: unknown key 'item[2].extra' in [item[2]] (valid keys: name)");
  EXPECT_EQ(resolved["item"][1]["name"].value<std::string>(), "two");
  EXPECT_EQ(resolved["whole"]["x"].value<std::int64_t>(), 1);
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
  const std::string msg = input_error_message([&] { load_toml(missing); });
  EXPECT_EQ(msg, "config file " + missing.string() + " does not exist");
}

TEST_F(ConfigFile, LoadTomlSyntaxErrorNamesFileAndLine) {
  const fs::path p = write("broken.toml", "a = 1\n\nb = = 2\n");
  const std::string msg = input_error_message([&] { load_toml(p); });
  EXPECT_TRUE(msg.starts_with(p.string() + ":3:")) << msg;
  const fs::path ok = write("ok.toml", "a = 1\n[t]\nb = \"x\"\n");
  const toml::table t = load_toml(ok);
  EXPECT_EQ(t["a"].value<std::int64_t>(), 1);
  EXPECT_EQ(t["t"]["b"].value<std::string>(), "x");
}

}  // namespace
}  // namespace qdmeta
