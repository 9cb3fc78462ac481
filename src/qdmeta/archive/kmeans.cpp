#include "qdmeta/archive/kmeans.hpp"

#include <algorithm>
#include <numeric>

#include "qdmeta/archive/nearest_centroid.hpp"
#include "qdmeta/core/error.hpp"
#include "qdmeta/core/parallel.hpp"
#include "qdmeta/core/rng.hpp"

namespace qdmeta {
namespace {

// Points per parallel chunk. Fixed, never derived from the thread count, so every chunk sees
// the same rows whatever the scheduling.
constexpr Index kChunk = 2048;

Index chunks_of(Index n) { return (n + kChunk - 1) / kChunk; }

// body(first, count) for every chunk of n rows, in parallel.
template <class Body>
void for_each_chunk(Index n, const Body& body) {
  parallel_indices(chunks_of(n), [&](Index c) { body(c * kChunk, std::min(kChunk, n - c * kChunk)); });
}

// Nearest centroid and exact squared distance of every row of `points`, in parallel.
void assign(const NearestCentroid& search, const RowMatrix& points, std::vector<Index>& cells,
            std::vector<double>& distances) {
  const Index n = points.rows();
  cells.resize(static_cast<std::size_t>(n));
  distances.resize(static_cast<std::size_t>(n));
  for_each_chunk(n, [&](Index first, Index count) {
    search.find(points.row(first).data(), count, cells.data() + first, distances.data() + first);
  });
}

double mean(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

// Rows of `points` picked by `rows`, in that order.
RowMatrix gather(const RowMatrix& points, const std::vector<Index>& rows) {
  RowMatrix out(static_cast<Index>(rows.size()), points.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Index>(i)) = points.row(rows[i]);
  return out;
}

// k-means++ (Arthur & Vassilvitskii 2007): each next centroid is a point drawn with probability
// proportional to its squared distance to the nearest centroid so far.
RowMatrix seed_plus_plus(const RowMatrix& points, Index k, Rng& rng) {
  const Index n = points.rows(), d = points.cols();
  RowMatrix centroids(k, d);
  std::vector<float> nearest(static_cast<std::size_t>(n), std::numeric_limits<float>::infinity());
  std::vector<double> chunk_sums(static_cast<std::size_t>(chunks_of(n)));
  Index chosen = static_cast<Index>(rng.below(static_cast<std::uint64_t>(n)));
  for (Index c = 0; c < k; ++c) {
    centroids.row(c) = points.row(chosen);
    const auto centre = centroids.row(c);
    // Lower each point's squared distance with the new centroid; sum each chunk.
    for_each_chunk(n, [&](Index first, Index count) {
      const auto block = points.middleRows(first, count);
      double sum = 0.0;
      for (Index i = 0; i < count; ++i) {
        const float dist = (block.row(i) - centre).squaredNorm();
        float& slot = nearest[static_cast<std::size_t>(first + i)];
        slot = std::min(slot, dist);
        sum += slot;
      }
      chunk_sums[static_cast<std::size_t>(first / kChunk)] = sum;
    });
    if (c + 1 == k) break;
    const double total = std::accumulate(chunk_sums.begin(), chunk_sums.end(), 0.0);
    if (!(total > 0.0)) {  // every point sits on a centroid: any point will do
      chosen = static_cast<Index>(rng.below(static_cast<std::uint64_t>(n)));
      continue;
    }
    double target = rng.uniform() * total;
    std::size_t chunk = 0;
    while (chunk + 1 < chunk_sums.size() && target >= chunk_sums[chunk]) target -= chunk_sums[chunk++];
    const Index first = static_cast<Index>(chunk) * kChunk;
    const Index last = std::min(n, first + kChunk);
    chosen = last - 1;
    for (Index i = first; i < last; ++i) {
      const double w = nearest[static_cast<std::size_t>(i)];
      if (target < w) {
        chosen = i;
        break;
      }
      target -= w;
    }
    // Rounding can leave the walk on a point already chosen (weight 0): take the last one of
    // the chunk with positive weight instead.
    while (nearest[static_cast<std::size_t>(chosen)] == 0.0f && chosen > first) --chosen;
  }
  return centroids;
}

RowMatrix seed_random(const RowMatrix& points, Index k, Rng& rng) {
  std::vector<Index> rows(static_cast<std::size_t>(points.rows()));
  std::iota(rows.begin(), rows.end(), Index{0});
  choose_without_replacement(rows, static_cast<std::size_t>(k), rng);
  return gather(points, rows);
}

// Per-centroid sums of the assigned points (double, in point order) and counts.
void accumulate(const RowMatrix& points, const std::vector<Index>& cells, Eigen::MatrixXd& sums,
                std::vector<std::int64_t>& counts) {
  sums.setZero();
  std::fill(counts.begin(), counts.end(), 0);
  for (Index i = 0; i < points.rows(); ++i) {
    const Index c = cells[static_cast<std::size_t>(i)];
    sums.row(c) += points.row(i).cast<double>();
    ++counts[static_cast<std::size_t>(c)];
  }
}

}  // namespace

void KMeansParams::validate() const {
  require(kCentroids, centroids);
  require(kSamples.from(centroids), samples);
  require(kInitSamples.from(centroids), init_samples);
  require(kIterations, iterations);
  require(kBatchSize, batch_size);
}

RowMatrix uniform_points(Index count, Index dimensions, std::uint64_t seed) {
  RowMatrix points(count, dimensions);
  Rng rng = Rng::stream(seed, {key(StreamKey::kCentroids), 0});
  Real* p = points.data();
  for (Index i = 0; i < points.size(); ++i) p[i] = static_cast<Real>(rng.uniform());
  return points;
}

double kmeans_cost(const RowMatrix& points, const RowMatrix& centroids) {
  const NearestCentroid search(centroids);
  std::vector<Index> cells;
  std::vector<double> distances;
  assign(search, points, cells, distances);
  return mean(distances);
}

KMeansResult kmeans(const RowMatrix& points, const KMeansParams& params) {
  KMeansParams p = params;
  p.samples = points.rows();  // the points are given: check that there are enough
  p.validate();
  const Index n = points.rows(), k = p.centroids, d = points.cols();

  KMeansResult result;
  Rng seeding = Rng::stream(p.seed, {key(StreamKey::kCentroids), 1});
  if (p.init == KMeansInit::kRandom) {
    result.centroids = seed_random(points, k, seeding);
  } else if (p.init_samples >= n) {
    result.centroids = seed_plus_plus(points, k, seeding);
  } else {
    std::vector<Index> rows(static_cast<std::size_t>(n));
    std::iota(rows.begin(), rows.end(), Index{0});
    choose_without_replacement(rows, static_cast<std::size_t>(p.init_samples), seeding);
    result.centroids = seed_plus_plus(gather(points, rows), k, seeding);
  }

  std::vector<Index> cells;
  std::vector<double> distances;
  Eigen::MatrixXd sums(k, d);
  std::vector<std::int64_t> counts(static_cast<std::size_t>(k));
  if (p.method == KMeansMethod::kLloyd) {
    for (int it = 0; it < p.iterations; ++it) {
      assign(NearestCentroid(result.centroids), points, cells, distances);
      result.cost.push_back(mean(distances));
      accumulate(points, cells, sums, counts);
      for (Index c = 0; c < k; ++c)  // an empty cluster keeps its centroid
        if (const auto m = counts[static_cast<std::size_t>(c)]; m > 0)
          result.centroids.row(c) = (sums.row(c) / static_cast<double>(m)).cast<Real>();
    }
  } else {
    // Mini-batch k-means: each step assigns a batch drawn with replacement, then moves every
    // centroid to the running mean of all points ever assigned to it (per-centroid learning
    // rate 1 / count), which does not depend on the order of the batch.
    std::vector<std::int64_t> seen(static_cast<std::size_t>(k), 0);
    std::vector<Index> rows(static_cast<std::size_t>(std::min(p.batch_size, n)));
    for (int it = 0; it < p.iterations; ++it) {
      Rng draw = Rng::stream(p.seed, {key(StreamKey::kCentroids), 2, static_cast<std::uint64_t>(it)});
      for (auto& r : rows) r = static_cast<Index>(draw.below(static_cast<std::uint64_t>(n)));
      const RowMatrix batch = gather(points, rows);
      assign(NearestCentroid(result.centroids), batch, cells, distances);
      result.cost.push_back(mean(distances));
      accumulate(batch, cells, sums, counts);
      for (Index c = 0; c < k; ++c) {
        const auto m = counts[static_cast<std::size_t>(c)];
        if (m == 0) continue;
        auto& total = seen[static_cast<std::size_t>(c)];
        total += m;
        const Eigen::RowVectorXd old = result.centroids.row(c).cast<double>();
        result.centroids.row(c) = (old + (sums.row(c) - static_cast<double>(m) * old) / static_cast<double>(total)).cast<Real>();
      }
    }
  }
  result.cost.push_back(kmeans_cost(points, result.centroids));
  return result;
}

KMeansResult cvt_centroids(Index dimensions, const KMeansParams& params) {
  params.validate();
  require_range("cvt dimensions", dimensions, Index{1}, Index{100'000});
  return kmeans(uniform_points(params.samples, dimensions, params.seed), params);
}

}  // namespace qdmeta
