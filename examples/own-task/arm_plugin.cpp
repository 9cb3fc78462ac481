#include "arm_plugin.hpp"

#include <qdmeta/plugin/config.hpp>
#include <qdmeta/plugin/task_registry.hpp>

#include "arm_task.hpp"
#include "locked_joint.hpp"

namespace arm {

// [task]: every key goes through the ConfigReader, so a misspelt one is refused.
qdmeta::Task read_arm(qdmeta::ConfigReader& task_table) {
  const auto joints = task_table.integer("joints", 10, 1, 1000);
  return qdmeta::Task(ArmTask(static_cast<int>(joints)));
}

namespace {

// `qdmeta adapt --test locked`.
std::unique_ptr<qdmeta::AdaptationTests> read_tests(const toml::table& /*run_config*/, const std::string& /*source*/,
                                                    const qdmeta::Task& task, std::string_view /*test*/,
                                                    std::uint64_t /*seed*/) {
  return std::make_unique<LockedJointTests>(task);
}

}  // namespace

void register_arm_task() {
  qdmeta::TaskPlugin plugin;
  plugin.read_task = read_arm;
  plugin.meta_objectives = {{"locked-joint", read_locked_joint}};
  plugin.read_adaptation_tests = read_tests;
  plugin.adaptation_tests = {"locked"};
  qdmeta::register_task_plugin("arm", std::move(plugin));
}

}  // namespace arm
