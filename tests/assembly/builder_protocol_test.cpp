// The builder protocol of src/qdmeta/plugin/algorithm_registry.hpp, run by build_run around
// every builder: a builder only reads, estimates and returns a maker; build_run checks every key
// (whether or not the builder finished its tables), then the memory estimate, and calls the
// maker only for a run. A builder written as carelessly as possible still gets every check.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "expect_input_error.hpp"
#include "qdmeta/assembly/build.hpp"
#include "qdmeta/assembly/core_plugins.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"

namespace qdmeta {
namespace {

// Registers "careless": reads [careless] a and nothing else, never calls finish() nor checks
// memory, adds `bytes` to the estimate, and builds MAP-Elites through a maker that counts its calls.
void register_careless(double bytes, int& calls) {
  ensure_core_plugins();
  const auto map_elites = find_algorithm("map-elites");
  register_algorithm("careless", [map_elites, bytes, &calls](AlgorithmBuild& b) -> AlgorithmMaker {
    ConfigReader mine = b.root.table("careless");
    (void)mine.integer("a", 0, 0, 10);
    b.built.memory.add("a careless buffer", "careless.a", bytes);
    AlgorithmMaker inner = (*map_elites)(b);
    return [inner = std::move(inner), &calls]() mutable {
      ++calls;
      return inner();
    };
  });
}

toml::table config(const std::string& careless_table) {
  return toml::parse("algorithm = \"careless\"\n[budget]\nevaluations = 100\n[careless]\n" + careless_table);
}

TEST(BuilderProtocol, ABuilderThatNeverFinishesStillGetsTheMisspeltKeyError) {
  int calls = 0;
  register_careless(0, calls);
  for (const BuildScope scope : {BuildScope::kRun, BuildScope::kTasksOnly})
    EXPECT_INPUT_ERROR(build_run(config("a = 1\nbb = 2\n"), "x.toml", {}, scope),
                       "x.toml: unknown key 'careless.bb' in [careless] (valid keys: a)");
  // The tables it reads through MAP-Elites's builder, which no longer finishes them either.
  EXPECT_INPUT_ERROR(build_run(config("a = 1\n[map_elites]\nbatch_sise = 5\n"), "x.toml", {}),
                     "x.toml: unknown key 'map_elites.batch_sise' in [map_elites] (valid keys: batch_size, "
                     "initial_population)");
  EXPECT_EQ(calls, 0) << "a refused config made an algorithm";
  const BuiltRun built = build_run(config("a = 1\n"), "x.toml", {});
  EXPECT_EQ(calls, 1);
  ASSERT_NE(built.algorithm, nullptr);
  EXPECT_EQ(built.algorithm->name(), "map-elites");
  EXPECT_EQ(built.resolved["careless"]["a"].value<std::int64_t>(), 1);
}

TEST(BuilderProtocol, TheMemoryEstimateIsCheckedBeforeTheMakerRunsAndOnlyForARun) {
  if (!memory_limit()) GTEST_SKIP() << "no memory limit can be read on this machine";
  int calls = 0;
  register_careless(1e30, calls);
  const std::string message = input_error_message([&] { build_run(config("a = 1\n"), "x.toml", {}); });
  EXPECT_TRUE(message.starts_with("x.toml: this run needs at least ")) << message;
  EXPECT_NE(message.find("for a careless buffer (careless.a)"), std::string::npos) << message;
  EXPECT_EQ(calls, 0);
  // What an MPI worker builds: the tasks, every key checked, no algorithm, so no memory needed.
  const BuiltRun tasks_only = build_run(config("a = 1\n"), "x.toml", {}, BuildScope::kTasksOnly);
  EXPECT_EQ(tasks_only.algorithm, nullptr);
  EXPECT_EQ(tasks_only.evaluation_tasks.size(), 1u);
  EXPECT_EQ(calls, 0);
}

TEST(BuilderProtocol, ABuilderThatReturnsNoMakerIsAnErrorForARunOnly) {
  ensure_core_plugins();
  register_algorithm("makes-nothing", [](AlgorithmBuild&) -> AlgorithmMaker { return {}; });
  const toml::table cfg = toml::parse("algorithm = \"makes-nothing\"\n");
  EXPECT_EQ(build_run(cfg, "x.toml", {}, BuildScope::kTasksOnly).algorithm, nullptr);
  try {
    build_run(cfg, "x.toml", {});
    FAIL() << "a run was built without an algorithm";
  } catch (const InputError&) {
    FAIL() << "a builder's fault reported as the config's";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "x.toml: the builder of algorithm 'makes-nothing' returned no maker");
  }
}

}  // namespace
}  // namespace qdmeta
