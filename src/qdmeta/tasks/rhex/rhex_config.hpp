#pragma once
// Makes `[task] name = "rhex"` and its [meta_fitness] available to config files
// (plugin/task_registry.hpp). The CLI calls this once at start-up; docs/config.md lists the keys.
namespace qdmeta {
void register_rhex_task();
}  // namespace qdmeta
