// Every qdmeta header that docs/library.md's program (examples/own-task) includes.
#include <qdmeta/cli/builtin_plugins.hpp>
#include <qdmeta/cli/run_cli.hpp>
#include <qdmeta/core/adaptation_tests.hpp>
#include <qdmeta/core/error.hpp>
#include <qdmeta/core/meta_objective.hpp>
#include <qdmeta/core/task.hpp>
#include <qdmeta/eval/evaluator.hpp>
#include <qdmeta/plugin/config.hpp>
#include <qdmeta/plugin/task_registry.hpp>
