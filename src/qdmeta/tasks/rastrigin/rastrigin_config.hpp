#pragma once
// Makes `[task] name = "rastrigin"`, its [meta_fitness] kinds ("translation", the default, and
// "dimension") and its test families ("dimension", "translation") available to config files
// through the task registry (plugin/task_registry.hpp), the same way the RHex task is and a
// user's task would be. ensure_core_plugins() calls it (assembly/core_plugins.hpp);
// docs/config.md lists the keys.
namespace qdmeta {
void register_rastrigin_task();
}  // namespace qdmeta
