#pragma once
// Makes `[task] name = "arm"`, its [meta_fitness] kind "locked-joint" and its test family
// "locked" available to qdmeta's config files and command line.
namespace arm {
void register_arm_task();
}  // namespace arm
