// The task registry: a meta-objective joins a registered task's kinds (a new kind after the
// task's own, a known kind replaced in place), and adding one to a task nobody registered is a
// qdmeta::Error naming the task, the library's one exception type.
#include "qdmeta/plugin/task_registry.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

std::vector<std::string> kinds_of(const std::string& task) {
  std::vector<std::string> kinds;
  for (const auto& [kind, reader] : find_task_plugin(task)->meta_objectives) kinds.push_back(kind);
  return kinds;
}

TEST(TaskRegistry, MetaObjectivesJoinARegisteredTasksKinds) {
  TaskPlugin plugin;
  plugin.meta_objectives.emplace_back("own", MetaObjectiveReader{});
  register_task_plugin("task-registry-test", plugin);
  register_meta_objective("task-registry-test", "added", {});
  register_meta_objective("task-registry-test", "own", {});  // replaced, keeps its place
  EXPECT_EQ(kinds_of("task-registry-test"), (std::vector<std::string>{"own", "added"}));
  EXPECT_TRUE(unregister_meta_objective("task-registry-test", "added"));
  EXPECT_EQ(kinds_of("task-registry-test"), (std::vector<std::string>{"own"}));
  EXPECT_TRUE(unregister_task_plugin("task-registry-test"));
}

TEST(TaskRegistry, AMetaObjectiveForAnUnregisteredTaskIsAnError) {
  try {
    register_meta_objective("task-nobody-registered", "kind", {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "register_meta_objective: task 'task-nobody-registered' is not registered");
  }
}

}  // namespace
}  // namespace qdmeta
