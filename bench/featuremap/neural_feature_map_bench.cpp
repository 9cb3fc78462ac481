// QD-Meta's feature-map on blocks of base features (K = 222, 542, 192 networks) and the
// vectorised exp beneath its sigmoid, against std::exp.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "qdmeta/featuremap/neural_feature_map.hpp"

namespace {

using qdmeta::Index;
using qdmeta::Real;

std::vector<Real> uniform(std::size_t n, float lo, float hi, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<Real> v(n);
  for (Real& x : v) x = u(rng);
  return v;
}

void BM_FastExp(benchmark::State& state) {
  const std::vector<Real> x = uniform(4096, -20.0f, 20.0f, 1);
  std::vector<Real> y(x.size());
  for (auto _ : state) {
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = qdmeta::fast_exp(x[i]);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
}
BENCHMARK(BM_FastExp);

void BM_StdExp(benchmark::State& state) {
  const std::vector<Real> x = uniform(4096, -20.0f, 20.0f, 1);
  std::vector<Real> y(x.size());
  for (auto _ : state) {
    for (std::size_t i = 0; i < x.size(); ++i) y[i] = std::exp(x[i]);
    benchmark::DoNotOptimize(y.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
}
BENCHMARK(BM_StdExp);

// map() over 65,536 rows; args: N_b, N_t (N_h = 10).
void BM_NeuralFeatureMap(benchmark::State& state) {
  qdmeta::NeuralFeatureMapShape shape;
  shape.inputs = state.range(0);
  shape.outputs = state.range(1);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> w(static_cast<std::size_t>(shape.weight_count()));
  for (double& x : w) x = u(rng);
  const qdmeta::NeuralFeatureMap map(shape, w);
  const Index rows = 65536;
  const std::vector<Real> base = uniform(static_cast<std::size_t>(rows * shape.inputs), 0.0f, 1.0f, 3);
  std::vector<Real> target(static_cast<std::size_t>(rows * shape.outputs));
  for (auto _ : state) {
    map.map(base.data(), rows, target.data());
    benchmark::DoNotOptimize(target.data());
  }
  state.SetItemsProcessed(state.iterations() * rows);
}
BENCHMARK(BM_NeuralFeatureMap)->Args({20, 2})->Args({50, 4})->Args({15, 4})->Unit(benchmark::kMicrosecond);

}  // namespace

// The network kernel alone on a transposed block that stays in L1 (512 rows, 20 -> 10 -> 2):
// what a map rebuild pays per row before binning and winner selection.
void BM_NetworkKernel(benchmark::State& state) {
  qdmeta::NeuralFeatureMapShape shape;
  shape.inputs = 20;
  shape.outputs = 2;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> w(static_cast<std::size_t>(shape.weight_count()));
  for (double& x : w) x = u(rng);
  const qdmeta::NeuralFeatureMap map(shape, w);
  const Index rows = 512;
  const std::vector<Real> base_t = uniform(static_cast<std::size_t>(rows * shape.inputs), 0.0f, 1.0f, 3);
  std::vector<Real> target_t(static_cast<std::size_t>(rows * shape.outputs));
  for (auto _ : state) {
    map.map_transposed(base_t.data(), rows, rows, target_t.data(), rows);
    benchmark::DoNotOptimize(target_t.data());
  }
  state.SetItemsProcessed(state.iterations() * rows);
}
BENCHMARK(BM_NetworkKernel);
