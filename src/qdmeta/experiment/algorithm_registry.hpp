#pragma once
// Algorithms, found by the name that the config's `algorithm` key selects: the four built-in
// ones (experiment/builtin_algorithms.hpp) and any a program registers, all through
// register_algorithm() into one Registry (plugin/registry.hpp). A builder reads its own config
// tables, adds what it will allocate to the memory estimate, and builds the algorithm.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "qdmeta/algorithms/algorithm.hpp"
#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/task.hpp"
#include "qdmeta/experiment/build.hpp"

namespace qdmeta {

class ConfigReader;

// What build_run() hands a builder once the shared tables ([budget], [task], [mutation], ...)
// are read.
struct AlgorithmBuild {
  ConfigReader& root;           // the whole config: the builder reads (and finish()es) its own tables
  Task task;                    // the run's task, the builder's to move into the algorithm
  MutationParams mutation;
  const RunSettings& settings;  // seed, budget, what the budget counts
  BuiltRun& built;              // the builder adds to built.memory and (its meta-objective's) built.evaluation_tasks
  bool make;                    // false for BuildScope::kTasksOnly: read and check everything, build nothing
  // Throws InputError naming the keys when built.memory exceeds the machine's limit; call it
  // after adding the estimates and before allocating. Does nothing unless `make`.
  void check_memory() const;
};

// Returns the algorithm, or nullptr when !build.make.
using AlgorithmBuilder = std::function<std::unique_ptr<Algorithm>(AlgorithmBuild& build)>;

// Registers (or replaces) the builder for `name`. Thread-safe. The config's default is
// "map-elites" where registered, else the first name registered.
void register_algorithm(const std::string& name, AlgorithmBuilder builder);
// The builder registered under `name`, or nullptr: a snapshot, which later registrations (of this
// name too) leave unchanged.
std::shared_ptr<const AlgorithmBuilder> find_algorithm(std::string_view name);
// Registered names in registration order.
std::vector<std::string> registered_algorithm_names();

}  // namespace qdmeta
