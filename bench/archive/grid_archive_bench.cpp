// Insertion into a 100 x 100 grid archive of 20-gene solutions: a batch of 400 random
// candidates into an archive that is already full (the common case late in a run), in one
// add_batch call (before the batch add: 400 calls of the per-row add).
#include <benchmark/benchmark.h>

#include "qdmeta/archive/grid_archive.hpp"

namespace {

void BM_GridArchiveAdd(benchmark::State& state) {
  qdmeta::GridArchiveParams p;
  p.solution_size = 20;
  qdmeta::GridArchive archive(p);
  qdmeta::Rng rng(3);
  qdmeta::RowMatrix solutions(400, 20), measures(400, 2);
  std::vector<float> objectives(400);
  for (qdmeta::Index k = 0; k < solutions.size(); ++k) solutions.data()[k] = static_cast<float>(rng.uniform());
  for (int fill = 0; fill < 100; ++fill)
    for (int r = 0; r < 400; ++r) {
      const float m[2] = {static_cast<float>(rng.uniform()), static_cast<float>(rng.uniform())};
      archive.add({solutions.row(r).data(), 20}, static_cast<float>(-rng.uniform() * 100), m);
    }
  for (qdmeta::Index k = 0; k < measures.size(); ++k) measures.data()[k] = static_cast<float>(rng.uniform());
  for (auto& o : objectives) o = static_cast<float>(-rng.uniform() * 100);
  for (auto _ : state) {
    archive.add_batch({solutions, objectives, measures, {}, {}});
    benchmark::DoNotOptimize(archive.size());
  }
  state.SetItemsProcessed(state.iterations() * 400);
}
BENCHMARK(BM_GridArchiveAdd);

}  // namespace
