// AURORA's autoencoder (20 -> 32 -> 8 -> 2 -> 8 -> 32 -> 20) on 10,000 rows of 20-D inputs: one
// retraining at its worst (all 100 epochs, early stopping off), one with the paper's early
// stopping, and encoding the rows (what a rebuild does).
#include <benchmark/benchmark.h>

#include "qdmeta/featuremap/autoencoder.hpp"

namespace {

qdmeta::RowMatrix rows(qdmeta::Index n) {
  qdmeta::Rng rng(1);
  qdmeta::RowMatrix x(n, 20);
  for (qdmeta::Index i = 0; i < x.size(); ++i) x.data()[i] = static_cast<qdmeta::Real>(rng.uniform());
  return x;
}

void retrain(benchmark::State& state, bool early_stopping) {
  const qdmeta::RowMatrix x = rows(10'000);
  qdmeta::AutoencoderParams p;
  if (!early_stopping) p.stopping_window = 1'000'000;
  int epochs = 0;
  for (auto _ : state) {
    qdmeta::Rng init(2), rng(3);
    qdmeta::Autoencoder ae(p, init);
    epochs = ae.train(x, rng).epochs;
  }
  state.counters["epochs"] = epochs;
}
void BM_AutoencoderRetrain100Epochs(benchmark::State& state) { retrain(state, false); }
void BM_AutoencoderRetrainEarlyStopping(benchmark::State& state) { retrain(state, true); }
BENCHMARK(BM_AutoencoderRetrain100Epochs)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AutoencoderRetrainEarlyStopping)->Unit(benchmark::kMillisecond);

void BM_AutoencoderEncode10k(benchmark::State& state) {
  const qdmeta::RowMatrix x = rows(10'000);
  qdmeta::Rng init(2);
  const qdmeta::Autoencoder ae({}, init);
  for (auto _ : state) benchmark::DoNotOptimize(ae.encode(x.data(), x.rows()).data());
  state.SetItemsProcessed(state.iterations() * x.rows());
}
BENCHMARK(BM_AutoencoderEncode10k)->Unit(benchmark::kMillisecond);

}  // namespace
