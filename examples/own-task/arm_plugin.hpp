#pragma once
// Makes `[task] name = "arm"`, its [meta_fitness] kind "locked-joint" and its test family
// "locked" available to qdmeta's config files and command line.
#include <qdmeta/core/task.hpp>

namespace qdmeta {
class ConfigReader;
}

namespace arm {
// [task] name = "arm": key `joints` (default 10); a misspelt key is refused.
qdmeta::Task read_arm(qdmeta::ConfigReader& task_table);

void register_arm_task();
}  // namespace arm
