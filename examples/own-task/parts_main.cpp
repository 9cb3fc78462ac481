// arm-parts: the arm run by a program that registers nothing. Its task and meta-objective are
// handed to build_run() as values (qdmeta/assembly/run_parts.hpp), and the config names them:
// the task part reads its own [task] keys (`joints`), as the registered arm of arm-qd does, so
// both programs run the same config files.
//   arm-parts run CONFIG DIR    a new run into DIR
//   arm-parts resume DIR        an interrupted run continued from its checkpoint
#include <qdmeta/assembly/run_parts.hpp>
#include <qdmeta/eval/evaluator.hpp>
#include <qdmeta/run/run.hpp>
#include <qdmeta/run/run_directory.hpp>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include "arm_plugin.hpp"
#include "locked_joint.hpp"

namespace {

constexpr int kThreads = 2;

qdmeta::RunParts arm_parts() {
  qdmeta::RunParts parts;
  parts.task_reader = qdmeta::TaskPart{"arm", arm::read_arm};  // made from the config's [task] table
  parts.meta_objective = qdmeta::MetaObjectivePart{"locked-joint", arm::read_locked_joint};  // one per run
  return parts;
}

int new_run(const std::string& config_file, const std::filesystem::path& dir) {
  qdmeta::BuiltRun built = qdmeta::build_run(toml::parse_file(config_file), config_file, {}, arm_parts());
  qdmeta::start_run_directory(dir, built, config_file, kThreads, /*overwrite=*/false);
  const auto evaluator = qdmeta::make_evaluator(kThreads);
  const auto result = qdmeta::run_to_budget(*built.algorithm, *evaluator, built.settings, dir);
  return result.reason == qdmeta::StopReason::kBudget ? 0 : 1;
}

int resumed_run(const std::filesystem::path& dir) {
  qdmeta::ResumableRun run = qdmeta::open_for_resume(dir, arm_parts());  // the parts it was made with
  const auto evaluator = qdmeta::make_evaluator(kThreads);
  const auto result =
      qdmeta::run_to_budget(*run.built.algorithm, *evaluator, run.built.settings, dir, {}, nullptr, &run.cursor);
  return result.reason == qdmeta::StopReason::kBudget ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  try {
    if (command == "run" && argc == 4) return new_run(argv[2], argv[3]);
    if (command == "resume" && argc == 3) return resumed_run(argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "arm-parts: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr, "usage: arm-parts run CONFIG DIR | arm-parts resume DIR\n");
  return 2;
}
