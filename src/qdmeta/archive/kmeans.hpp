#pragma once
// Centroids for CVT archives (docs/specification.md, CVT-MAP-Elites): k-means over points drawn uniformly in the
// base-feature space [0,1]^d. Seeding by k-means++ (on a subsample) or by distinct random
// points; then full-batch Lloyd iterations or mini-batch updates (Sculley 2010, the authors'
// choice through scikit-learn). Nearest centroids are exact (archive/nearest_centroid.hpp) and
// every reduction runs in a fixed order, so the centroids are the same bits at any thread count.
// Work is spread over oneTBB's threads: run it inside a task arena to limit them.
#include <cstdint>
#include <vector>

#include "qdmeta/core/params.hpp"
#include "qdmeta/core/types.hpp"

namespace qdmeta {

enum class KMeansInit { kPlusPlus, kRandom };
inline constexpr EnumNames<KMeansInit, 2> kKMeansInitNames{
    {{KMeansInit::kPlusPlus, "k-means++"}, {KMeansInit::kRandom, "random"}}};

enum class KMeansMethod { kLloyd, kMiniBatch };
inline constexpr EnumNames<KMeansMethod, 2> kKMeansMethodNames{
    {{KMeansMethod::kLloyd, "lloyd"}, {KMeansMethod::kMiniBatch, "mini-batch"}}};

struct KMeansParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp).
  static constexpr IntParam kCentroids{"cvt", "centroids", 1, 10'000'000, "number of cells"};
  static constexpr IntParam kSamples{"cvt", "samples", 1, 1'000'000'000, "uniform random points k-means runs on"};
  static constexpr IntParam kInitSamples{"cvt", "init_samples", 1, 1'000'000'000,
      "k-means++ seeds from this many of the points, drawn without replacement (all when larger than "
      "`samples`)"};
  static constexpr IntParam kIterations{"cvt", "iterations", 0, 1'000'000,
      "Lloyd passes or mini-batch steps after seeding"};
  static constexpr IntParam kBatchSize{"cvt", "batch_size", 1, 1'000'000'000, "mini-batch: points per step"};
  Index centroids = 10'000;            // k, >= 1
  Index samples = 1'000'000;           // random points drawn in [0,1]^d, >= centroids
  KMeansInit init = KMeansInit::kPlusPlus;
  Index init_samples = 100'000;        // k-means++ seeds from this many of the points (>= centroids)
  KMeansMethod method = KMeansMethod::kLloyd;
  int iterations = 10;                 // Lloyd passes over all points, or mini-batch steps, >= 0
  Index batch_size = 100'000;          // mini-batch: points per step
  std::uint64_t seed = 1;              // seed of the points, the seeding and the batches
  void validate() const;
};

struct KMeansResult {
  RowMatrix centroids;  // k x d
  // Mean squared distance of the points to their nearest centroid, before each iteration and
  // after the last (Lloyd: over all points; mini-batch: over each step's batch, then over all).
  std::vector<double> cost;
};

// Points drawn uniformly in [0,1]^dimensions (count x dimensions) from (seed, kCentroids).
RowMatrix uniform_points(Index count, Index dimensions, std::uint64_t seed);

// k-means of `points` (rows). `params.samples` is ignored: the points are given.
KMeansResult kmeans(const RowMatrix& points, const KMeansParams& params);

// The mean exact squared distance of `points` to their nearest centroid.
double kmeans_cost(const RowMatrix& points, const RowMatrix& centroids);

// CVT centroids: k-means over params.samples uniform points in [0,1]^dimensions.
KMeansResult cvt_centroids(Index dimensions, const KMeansParams& params);

}  // namespace qdmeta
