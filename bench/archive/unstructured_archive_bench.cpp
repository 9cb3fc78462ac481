// AURORA's neighbour queries at 10,000 members in a 2-D latent space (z-scored Gaussian-like
// codes, as the archive holds them): the 16 nearest of a point near a member, by the archive's
// grid, by a brute-force scan with a running k-selection, and by a nanoflann k-d tree (built
// once, queries only: a lower bound for a tree that must also follow insertions and
// replacements). Plus a rebuild: re-adding 10,000 members through the insertion rule, one add()
// at a time and by refill(); and offspring-like adds into an archive packed by the rule as
// AURORA's is at its target (BM_AddNearMembers).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "qdmeta/archive/unstructured_archive.hpp"

#if __has_include(<nanoflann.hpp>)
#include <nanoflann.hpp>
#define QDMETA_HAVE_NANOFLANN 1
#endif

namespace {

using qdmeta::Index;
using qdmeta::Real;

constexpr Index kMembers = 10'000;
constexpr Index kNeighbours = 16;  // k + 1 with k = 15

std::vector<Real> latent_points(Index n, std::uint64_t seed) {
  qdmeta::Rng rng(seed);
  std::vector<Real> p(static_cast<std::size_t>(2 * n));
  for (auto& x : p) x = static_cast<Real>(rng.normal());
  return p;
}

qdmeta::UnstructuredArchive filled_archive(const std::vector<Real>& points) {
  qdmeta::UnstructuredArchiveParams params;
  params.solution_size = 1;
  qdmeta::UnstructuredArchive a(params);
  const Real zero = 0;
  for (Index i = 0; i < kMembers; ++i) a.add(&zero, 0, points.data() + 2 * i, nullptr, 1e-9);
  return a;
}

std::vector<Real> queries(const std::vector<Real>& points) {
  std::vector<Real> q(points);
  for (auto& x : q) x += 0.01f;
  return q;
}

void BM_NearestGrid(benchmark::State& state) {
  const auto points = latent_points(kMembers, 1);
  const auto archive = filled_archive(points);
  const auto q = queries(points);
  Index i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(archive.nearest(q.data() + 2 * i, kNeighbours));
    i = (i + 1) % kMembers;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_NearestGrid);

void BM_NearestBruteForce(benchmark::State& state) {
  const auto points = latent_points(kMembers, 1);
  const auto q = queries(points);
  std::vector<Real> x(kMembers), y(kMembers), d2(kMembers);
  for (Index i = 0; i < kMembers; ++i) x[i] = points[2 * i], y[i] = points[2 * i + 1];
  std::vector<std::pair<Real, Index>> best;
  Index i = 0;
  for (auto _ : state) {
    const Real qx = q[2 * i], qy = q[2 * i + 1];
    for (Index j = 0; j < kMembers; ++j) d2[j] = (x[j] - qx) * (x[j] - qx) + (y[j] - qy) * (y[j] - qy);
    best.clear();
    Real worst = std::numeric_limits<Real>::infinity();
    for (Index j = 0; j < kMembers; ++j) {
      if (d2[j] >= worst) continue;
      best.insert(std::upper_bound(best.begin(), best.end(), std::pair{d2[j], j}), {d2[j], j});
      if (static_cast<Index>(best.size()) > kNeighbours) best.pop_back();
      if (static_cast<Index>(best.size()) == kNeighbours) worst = best.back().first;
    }
    benchmark::DoNotOptimize(best.data());
    i = (i + 1) % kMembers;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_NearestBruteForce);

#ifdef QDMETA_HAVE_NANOFLANN
struct Cloud {
  const std::vector<Real>* p;
  std::size_t kdtree_get_point_count() const { return p->size() / 2; }
  Real kdtree_get_pt(std::size_t i, std::size_t d) const { return (*p)[2 * i + d]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, Cloud>, Cloud, 2, std::uint32_t>;

void BM_NearestNanoflannStatic(benchmark::State& state) {
  const auto points = latent_points(kMembers, 1);
  const auto q = queries(points);
  const Cloud cloud{&points};
  Tree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  std::uint32_t idx[kNeighbours];
  Real dist[kNeighbours];
  Index i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tree.knnSearch(q.data() + 2 * i, kNeighbours, idx, dist));
    i = (i + 1) % kMembers;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_NearestNanoflannStatic);

void BM_NanoflannBuild(benchmark::State& state) {
  const auto points = latent_points(kMembers, 1);
  const Cloud cloud{&points};
  for (auto _ : state) {
    Tree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    benchmark::DoNotOptimize(&tree);
  }
}
BENCHMARK(BM_NanoflannBuild)->Unit(benchmark::kMicrosecond);
#endif

// A rebuild's re-adding: 10,000 members through the insertion rule, threshold so that about
// 10,000 stay (the archive at its target), as AURORA does every 10 generations.
void BM_UnstructuredArchiveRebuild(benchmark::State& state) {
  const auto points = latent_points(kMembers, 2);
  qdmeta::UnstructuredArchiveParams params;
  params.solution_size = 20;
  params.base_feature_size = 20;
  std::vector<Real> genes(20, 0.5f);
  qdmeta::Rng rng(3);
  std::vector<Real> fitness(kMembers);
  for (auto& f : fitness) f = static_cast<Real>(-300 + 50 * rng.normal());
  Index kept = 0;
  for (auto _ : state) {
    qdmeta::UnstructuredArchive a(params);
    for (Index i = 0; i < kMembers; ++i) a.add(genes.data(), fitness[i], points.data() + 2 * i, genes.data(), 0.01);
    kept = a.size();
  }
  state.counters["kept"] = static_cast<double>(kept);
  state.SetItemsProcessed(state.iterations() * kMembers);
}
BENCHMARK(BM_UnstructuredArchiveRebuild)->Unit(benchmark::kMillisecond);

// The same rows through refill(): rows apart from every earlier row enter without a query.
void BM_UnstructuredArchiveRefill(benchmark::State& state) {
  const auto points = latent_points(kMembers, 2);
  qdmeta::UnstructuredArchiveParams params;
  params.solution_size = 20;
  params.base_feature_size = 20;
  std::vector<Real> genes(20 * kMembers, 0.5f);
  qdmeta::Rng rng(3);
  std::vector<Real> fitness(kMembers);
  for (auto& f : fitness) f = static_cast<Real>(-300 + 50 * rng.normal());
  qdmeta::UnstructuredArchive a(params);
  for (auto _ : state) {
    a.refill(kMembers, genes.data(), fitness.data(), points.data(), genes.data(), 0.01);
    benchmark::DoNotOptimize(a.size());
  }
  state.counters["kept"] = static_cast<double>(a.size());
  state.SetItemsProcessed(state.iterations() * kMembers);
}
BENCHMARK(BM_UnstructuredArchiveRefill)->Unit(benchmark::kMillisecond);

// An archive packed by the insertion rule at AURORA's scale: candidates uniform in the disc of
// radius 2 (SD 1 per axis, as z-scored codes) added with l = 0.025 until about 12,000 remain,
// much as AURORA's archive sits at its 10,000 target (l about 0.025, members 0.023 or more
// apart).
constexpr double kPackedThreshold = 0.025;

qdmeta::UnstructuredArchive packed_archive() {
  qdmeta::UnstructuredArchiveParams params;
  params.solution_size = 20;
  params.base_feature_size = 20;
  qdmeta::UnstructuredArchive a(params);
  qdmeta::Rng rng(5);
  std::vector<Real> genes(20, 0.5f);
  for (int i = 0; i < 60'000; ++i) {
    double x, y;
    do {
      x = rng.uniform(-2, 2);
      y = rng.uniform(-2, 2);
    } while (x * x + y * y > 4);
    const Real d[2] = {static_cast<Real>(x), static_cast<Real>(y)};
    a.add(genes.data(), static_cast<Real>(-300 + 50 * rng.normal()), d, genes.data(), kPackedThreshold);
  }
  return a;
}

// Offspring-like candidates: a member's descriptor moved by N(0, 0.015) per axis and its
// fitness by N(0, 30), as a mutated member's code lands near its parent's. In a real run about
// 10% of offspring are added, 20% rejected by the second-nearest rule and 70% reach the
// eps-dominance test (a quarter of those replace); the counters give this benchmark's shares.
// A fixed count of adds, so that every build runs the same sequence (the archive changes as
// it goes).
void BM_AddNearMembers(benchmark::State& state) {
  auto a = packed_archive();
  qdmeta::Rng rng(7);
  std::vector<Real> genes(20, 0.5f);
  double statuses[3] = {0, 0, 0};
  for (auto _ : state) {
    const Index parent = a.sample(rng);
    const Real d[2] = {static_cast<Real>(a.descriptor(parent, 0) + 0.015 * rng.normal()),
                       static_cast<Real>(a.descriptor(parent, 1) + 0.015 * rng.normal())};
    const auto f = static_cast<Real>(a.objective(parent) + 30 * rng.normal());
    ++statuses[static_cast<int>(a.add(genes.data(), f, d, genes.data(), kPackedThreshold))];
  }
  const double n = statuses[0] + statuses[1] + statuses[2];
  state.counters["members"] = static_cast<double>(a.size());
  state.counters["rejected"] = statuses[static_cast<int>(qdmeta::AddStatus::kNotAdded)] / n;
  state.counters["added"] = statuses[static_cast<int>(qdmeta::AddStatus::kNew)] / n;
  state.counters["replaced"] = statuses[static_cast<int>(qdmeta::AddStatus::kImproved)] / n;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_AddNearMembers)->Iterations(200'000);

}  // namespace
