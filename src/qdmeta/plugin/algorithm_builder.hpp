#pragma once
// What an algorithm's builder is: the function build_run() calls with the config read so far
// (AlgorithmBuild), returning the maker of the algorithm (AlgorithmMaker). A builder is found by
// name in the registry (algorithm_registry.hpp) or handed to build_run() as a part
// (run_parts.hpp); either way build_run() runs the builder protocol around it.
//
// The builder protocol, run by build_run() around every builder so that none can skip a step:
//   1. the builder reads its own config tables through build.root, adds what it will allocate to
//      build.built.memory, and returns an AlgorithmMaker (nothing large is allocated yet);
//   2. build_run() checks every key of the config (ConfigReader::finish on the root reaches every
//      table the builder opened, finished or not), then, for a run, the memory estimate against
//      the machine's limit;
//   3. for a run only (never for BuildScope::kTasksOnly), build_run() calls the maker.
#include <functional>
#include <memory>
#include <type_traits>
#include <utility>

#include "qdmeta/core/mutation.hpp"
#include "qdmeta/core/task.hpp"

namespace qdmeta {

class Algorithm;  // algorithms/algorithm.hpp, which a builder includes
struct BuiltRun;
struct RunParts;
struct RunSettings;
class ConfigReader;

// What build_run() hands a builder once the shared tables ([budget], [task], [mutation], ...)
// are read.
struct AlgorithmBuild {
  ConfigReader& root;           // the whole config: the builder reads its own tables from it
  Task task;                    // the run's task, the builder's to move into its maker
  MutationParams mutation;
  const RunSettings& settings;  // seed, budget, what the budget counts
  BuiltRun& built;              // the builder adds to built.memory and (its meta-objective's) built.evaluation_tasks
  const RunParts& parts;        // what the caller handed over (read_meta_objective() looks here first)
};

// A builder's algorithm, made later (step 3 above). Move-only, so that it may own what the
// builder read (a meta-objective, a controller) by unique_ptr; called at most once.
class AlgorithmMaker {
 public:
  AlgorithmMaker() = default;
  template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, AlgorithmMaker> &&
             std::is_invocable_r_v<std::unique_ptr<Algorithm>, std::remove_cvref_t<F>&>)
  AlgorithmMaker(F&& make)  // implicit, as std::function's is: `return [..] { ... };`
      : impl_(std::make_unique<Holder<std::remove_cvref_t<F>>>(std::forward<F>(make))) {}
  explicit operator bool() const { return impl_ != nullptr; }
  // Defined beside Algorithm (algorithms/algorithm.cpp), which this layer may not include.
  std::unique_ptr<Algorithm> operator()();

 private:
  struct Base {
    virtual ~Base() = default;
    virtual std::unique_ptr<Algorithm> make() = 0;
  };
  template <class F>
  struct Holder final : Base {
    explicit Holder(F f) : make_algorithm(std::move(f)) {}
    std::unique_ptr<Algorithm> make() override { return make_algorithm(); }
    F make_algorithm;
  };
  std::unique_ptr<Base> impl_;
};

// Step 1 above: reads, estimates, and returns the maker (an empty one is an error at step 3).
using AlgorithmBuilder = std::function<AlgorithmMaker(AlgorithmBuild& build)>;

}  // namespace qdmeta
