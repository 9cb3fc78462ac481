#pragma once
// The test phase (paper section "Experiment setup"; docs/specification.md, Test phase): for each unseen
// test function, random search without replacement over the archive's solutions, recording the
// best score found after each evaluation; then the mean and standard error over the test
// functions. An archive smaller than the budget is exhausted and its best carried forward.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "qdmeta/core/adaptation_tests.hpp"
#include "qdmeta/eval/evaluator.hpp"

namespace qdmeta {

struct AdaptationCurve {
  std::vector<double> best_mean;  // [e]: mean over test functions of the best after e + 1 evaluations
  std::vector<double> best_se;    // [e]: its standard error (sample SD / sqrt(functions))
  std::vector<double> final_best; // [test]: each function's best at the end
};

// Test function t draws its search order from the stream (seed, kTest, t), so the result does
// not depend on the evaluator or on which functions run.
AdaptationCurve random_search_adaptation(const RowMatrix& archive, const AdaptationTests& tests, Index budget,
                                         std::uint64_t seed, Evaluator& evaluator);

// adapt-NAME.csv: `evaluations,best_mean,best_se`, one row per evaluation 1..budget. Atomic.
void write_adaptation_csv(const std::filesystem::path& path, const AdaptationCurve& curve);

// The generalisation test (docs/specification.md, Test phase; the paper's generalisation table): every archive
// solution in every environment of a group, no search. mean = over solutions x environments
// (dead = 0 is the task's business); se = SD over environments of their archive means / sqrt(E).
struct GeneralisationRow {
  std::string group;
  Index environments = 0;
  Index solutions = 0;
  double mean = 0.0;
  double se = 0.0;
};
GeneralisationRow whole_archive_mean(const RowMatrix& archive, const AdaptationTests& tests, Evaluator& evaluator);

// generalisation.csv: `group,environments,solutions,mean,se`, one row per group. Atomic.
void write_generalisation_csv(const std::filesystem::path& path, const std::vector<GeneralisationRow>& rows);

}  // namespace qdmeta
