// Whole-loop benchmark: AURORA-CSC-Uniform on 20-D Rastrigin with the paper's settings
// (configs/rastrigin/aurora.toml), 400,000 evaluations from scratch on 1 thread: 1,000
// generations with 14 trainings and 100 rebuilds, the archive at its 10,000 target from about
// generation 300. items_per_second = evaluations per second.
#include <benchmark/benchmark.h>

#include "qdmeta/algorithms/aurora.hpp"
#include "qdmeta/eval/evaluator.hpp"
#include "qdmeta/tasks/rastrigin/rastrigin_task.hpp"

namespace {

void BM_AuroraRastrigin(benchmark::State& state) {
  const std::int64_t budget = state.range(0);
  qdmeta::SerialEvaluator evaluator;
  for (auto _ : state) {
    qdmeta::Aurora a({}, qdmeta::Task{qdmeta::RastriginTask{}}, {}, 1);
    while (a.counters().bottom < budget) a.step(evaluator);
    state.counters["num_elites"] = static_cast<double>(a.archive().size());
    state.counters["trainings"] = static_cast<double>(a.trainings());
  }
  state.SetItemsProcessed(state.iterations() * budget);
}
BENCHMARK(BM_AuroraRastrigin)->Arg(400'000)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
