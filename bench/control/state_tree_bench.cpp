// The state tree's split search: the only part of SARSA(lambda) control whose cost grows with
// the run (a leaf's stored transitions). Measured on uninformative transitions of 6 attributes,
// where every candidate threshold is tried.
#include <benchmark/benchmark.h>

#include "qdmeta/control/state_tree.hpp"

namespace {

qdmeta::StateTree filled_tree(std::size_t transitions) {
  qdmeta::StateTreeParams p;
  p.attributes = 6;
  p.actions = 5;
  p.ks_alpha = 1e-12;  // never split, so every iteration searches the same leaf
  qdmeta::StateTree tree(p);
  qdmeta::Rng rng(1);
  for (std::size_t k = 0; k < transitions; ++k) {
    qdmeta::StateTransition t;
    for (int a = 0; a < 6; ++a) t.observation.push_back(rng.uniform());
    t.value = rng.normal();
    tree.node(0).transitions.push_back(std::move(t));
  }
  return tree;
}

void BM_StateTreeSplitSearch(benchmark::State& state) {
  qdmeta::StateTree tree = filled_tree(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(tree.try_split(0));
  state.SetLabel("transitions in the leaf");
}
BENCHMARK(BM_StateTreeSplitSearch)->Arg(61)->Arg(500)->Arg(5000)->Unit(benchmark::kMillisecond);

}  // namespace
