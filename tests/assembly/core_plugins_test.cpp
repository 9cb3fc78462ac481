// Tests of src/qdmeta/experiment/core_plugins.{hpp,cpp}: the built-in plugins register as a
// user's do, once, and only where no plugin of their name is registered, so a user's plugin of a
// built-in name wins whether it came first or last. The first case needs a process in which
// nothing has been registered yet, so it runs in a fresh one (a "threadsafe" death test
// re-executes this binary for it alone).
#include "qdmeta/assembly/core_plugins.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "qdmeta/assembly/build.hpp"
#include "qdmeta/plugin/algorithm_registry.hpp"
#include "qdmeta/plugin/config.hpp"
#include "qdmeta/plugin/task_registry.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace qdmeta {
namespace {

using Names = std::vector<std::string>;

// A "rastrigin" of its own: 7 genes whatever the config says, and a key the built-in lacks.
TaskPlugin seven_gene_rastrigin() {
  TaskPlugin plugin;
  plugin.read_task = [](ConfigReader& t) {
    (void)t.integer("own_key", 0, 0, 10);
    RastriginParams p;
    p.dimensions = 7;
    return Task(RastriginTask(p));
  };
  return plugin;
}

AlgorithmMaker build_nothing(AlgorithmBuild&) { return {}; }

// What a fresh process does when a user registers before anything else: returns the problems.
std::string register_first_then_build() {
  std::string problems;
  register_task_plugin("rastrigin", seven_gene_rastrigin());
  register_algorithm("mine", build_nothing);
  const BuiltRun built = build_run(toml::parse("[task]\nown_key = 3\n"), "x.toml", {}, BuildScope::kTasksOnly);
  if (built.evaluation_tasks.front().genotype_size() != 7) problems += "the built-in rastrigin replaced the user's; ";
  if (built.settings.algorithm != "map-elites") problems += "the default algorithm is " + built.settings.algorithm + "; ";
  if (registered_algorithm_names() != Names{"mine", "map-elites", "qd-meta", "cvt-map-elites", "aurora", "cma-me", "cma-mae"})
    problems += "the built-in algorithms are not all registered after the user's; ";
  return problems;
}

TEST(CorePlugins, AUserPluginRegisteredBeforeTheBuiltInsWins) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const std::string problems = register_first_then_build();
        std::cerr << problems;
        std::exit(problems.empty() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

TEST(CorePlugins, AUserPluginRegisteredAfterTheBuiltInsReplacesThem) {
  ensure_core_plugins();
  const auto builtin = find_task_plugin("rastrigin");
  ASSERT_NE(builtin, nullptr);
  register_task_plugin("rastrigin", seven_gene_rastrigin());
  const BuiltRun built = build_run(toml::parse("[task]\nown_key = 1\n"), "x.toml", {}, BuildScope::kTasksOnly);
  EXPECT_EQ(built.evaluation_tasks.front().genotype_size(), 7);
  register_task_plugin("rastrigin", *builtin);  // the other tests of this binary expect the built-in
  EXPECT_EQ(build_run(toml::table{}, "x.toml", {}, BuildScope::kTasksOnly).evaluation_tasks.front().genotype_size(), 20);
}

// Many threads asking at once: every call returns after the one registration, none deadlocks,
// and the registries hold each built-in once.
TEST(CorePlugins, RegisterOnceFromManyThreads) {
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) threads.emplace_back([] { ensure_core_plugins(); });
  for (auto& th : threads) th.join();
  ensure_core_plugins();
  const Names algorithms = registered_algorithm_names();
  for (const char* name : {"map-elites", "qd-meta", "cvt-map-elites", "aurora", "cma-me", "cma-mae"})
    EXPECT_EQ(std::count(algorithms.begin(), algorithms.end(), name), 1) << name;
  EXPECT_NE(find_task_plugin("rastrigin"), nullptr);
}

}  // namespace
}  // namespace qdmeta
