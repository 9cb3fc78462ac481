#include "qdmeta/archive/centroid_grid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "qdmeta/archive/reference_distance.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {
// Buckets per centroid: about two centroids to a bucket, so that a query's own ring and the next
// usually settle it.
constexpr double kBucketsPerCentroid = 0.5;
}  // namespace

CentroidGrid::CentroidGrid(const RowMatrix& centroids) : d_(centroids.cols()) {
  const Index k = centroids.rows();
  if (k < 1 || d_ < 1 || d_ > kMaxDimensions)
    throw InputError(fmt::format("centroid grid: {} x {} centroids: need at least one, of 1 to {} dimensions", k, d_,
                                 kMaxDimensions));
  if (!centroids.allFinite()) throw InputError("centroid grid: a centroid has a NaN or infinite coordinate");
  std::array<double, kMaxDimensions> extent{};
  double reach = 0.0;
  for (Index a = 0; a < d_; ++a) {
    const auto u = static_cast<std::size_t>(a);
    low_[u] = static_cast<double>(centroids.col(a).minCoeff());
    extent[u] = static_cast<double>(centroids.col(a).maxCoeff()) - low_[u];
    reach = std::max(reach, std::abs(low_[u]) + extent[u]);
  }
  // Square buckets of side s over the axes the centroids spread along, s chosen for the wanted
  // bucket count; an axis narrower than s gets one bucket and the rest share the count, so the
  // total stays under 2^d times the wanted count however flat the cloud is.
  const double wanted = std::max(1.0, kBucketsPerCentroid * static_cast<double>(k));
  std::array<bool, kMaxDimensions> spread{};
  for (Index a = 0; a < d_; ++a) spread[static_cast<std::size_t>(a)] = extent[static_cast<std::size_t>(a)] > 0;
  double side = 0.0;
  for (bool changed = true; changed;) {
    changed = false;
    double volume = 1.0;
    int axes = 0;
    for (Index a = 0; a < d_; ++a)
      if (spread[static_cast<std::size_t>(a)]) {
        volume *= extent[static_cast<std::size_t>(a)];
        ++axes;
      }
    if (axes == 0) break;
    side = std::pow(volume / wanted, 1.0 / axes);
    for (Index a = 0; a < d_; ++a)
      if (spread[static_cast<std::size_t>(a)] && extent[static_cast<std::size_t>(a)] < side) {
        spread[static_cast<std::size_t>(a)] = false;
        changed = true;
      }
  }
  Index total = 1;
  for (Index a = 0; a < d_; ++a) {
    const auto u = static_cast<std::size_t>(a);
    if (spread[u]) {
      buckets_[u] = std::max<Index>(1, static_cast<Index>(std::ceil(extent[u] / side)));
      width_[u] = extent[u] / static_cast<double>(buckets_[u]);
      inverse_[u] = static_cast<double>(buckets_[u]) / extent[u];
    } else {
      buckets_[u] = 1;
      width_[u] = 0.0;
      inverse_[u] = 0.0;
    }
    total *= buckets_[u];
  }
  // Bucket positions are computed in double from float coordinates: a centroid lands at most a
  // few units in the 16th digit of the box's size past its bucket's edge.
  margin_ = 1e-9 * reach + std::numeric_limits<double>::min();

  // Centroids by bucket (a counting sort, stable: increasing index within a bucket).
  std::vector<Index> bucket_of(static_cast<std::size_t>(k));
  start_.assign(static_cast<std::size_t>(total + 1), 0);
  for (Index c = 0; c < k; ++c) {
    Index b = 0;
    for (Index a = 0; a < kMaxDimensions; ++a)
      b = b * buckets_[static_cast<std::size_t>(a)] + (a < d_ ? bucket_along(a, static_cast<double>(centroids(c, a))) : 0);
    bucket_of[static_cast<std::size_t>(c)] = b;
    ++start_[static_cast<std::size_t>(b + 1)];
  }
  for (Index b = 0; b < total; ++b) start_[static_cast<std::size_t>(b + 1)] += start_[static_cast<std::size_t>(b)];
  std::vector<std::int32_t> next(start_.begin(), start_.end() - 1);
  index_.resize(static_cast<std::size_t>(k));
  coordinates_.resize(static_cast<std::size_t>(k * d_));
  for (Index c = 0; c < k; ++c) {
    const auto place = static_cast<std::size_t>(next[static_cast<std::size_t>(bucket_of[static_cast<std::size_t>(c)])]++);
    index_[place] = static_cast<std::int32_t>(c);
    std::copy_n(centroids.row(c).data(), d_, coordinates_.data() + place * static_cast<std::size_t>(d_));
  }
}

Index CentroidGrid::bucket_along(Index axis, double x) const {
  const auto u = static_cast<std::size_t>(axis);
  const double t = (x - low_[u]) * inverse_[u];
  if (!(t > 0)) return 0;
  if (t >= static_cast<double>(buckets_[u])) return buckets_[u] - 1;
  return static_cast<Index>(t);
}

Index CentroidGrid::find(const Real* point, double* distance) const {
  std::array<Index, kMaxDimensions> q{};
  for (Index a = 0; a < d_; ++a) {
    if (!std::isfinite(point[a])) return -1;
    q[static_cast<std::size_t>(a)] = bucket_along(a, static_cast<double>(point[a]));
  }
  Index best = -1;
  double best_squared = std::numeric_limits<double>::infinity();
  const auto visit = [&](std::int32_t first, std::int32_t last) {
    for (std::int32_t e = first; e < last; ++e) {
      const Real* centroid = coordinates_.data() + static_cast<std::size_t>(e) * static_cast<std::size_t>(d_);
      const double squared = reference_squared_distance(point, centroid, d_);
      const Index c = index_[static_cast<std::size_t>(e)];
      if (squared < best_squared || (squared == best_squared && c < best)) {
        best_squared = squared;
        best = c;
      }
    }
  };
  const auto entries = [&](Index b0, Index b1, Index b2) {
    return start_[static_cast<std::size_t>((b0 * buckets_[1] + b1) * buckets_[2] + b2)];
  };
  for (Index r = 0;; ++r) {
    // Ring r: the buckets whose largest step from q along an axis is r, inside the grid.
    std::array<Index, kMaxDimensions> lo{}, hi{};
    for (std::size_t a = 0; a < kMaxDimensions; ++a) {
      lo[a] = std::max<Index>(0, q[a] - r);
      hi[a] = std::min<Index>(buckets_[a] - 1, q[a] + r);
    }
    const auto run = [&](Index i0, Index i1) { visit(entries(i0, i1, lo[2]), entries(i0, i1, hi[2] + 1)); };
    for (Index i0 = lo[0]; i0 <= hi[0]; ++i0) {
      if (std::abs(i0 - q[0]) == r) {
        for (Index i1 = lo[1]; i1 <= hi[1]; ++i1) run(i0, i1);
      } else if (buckets_[2] == 1) {  // at most 2-D: only the two ends of the row are on the ring
        if (q[1] - r >= 0) run(i0, q[1] - r);
        if (q[1] + r < buckets_[1]) run(i0, q[1] + r);
      } else {
        for (Index i1 = lo[1]; i1 <= hi[1]; ++i1) {
          if (std::abs(i1 - q[1]) == r) {
            run(i0, i1);
          } else {  // inside the ring's cross-section: only its two ends along the last axis
            if (q[2] - r >= 0) visit(entries(i0, i1, q[2] - r), entries(i0, i1, q[2] - r + 1));
            if (q[2] + r < buckets_[2]) visit(entries(i0, i1, q[2] + r), entries(i0, i1, q[2] + r + 1));
          }
        }
      }
    }
    // Every centroid not yet visited lies in a bucket beyond ring r along some axis, so at least
    // this far from the point (less the rounding margin of bucket positions).
    double beyond = std::numeric_limits<double>::infinity();
    bool left = false;
    for (Index a = 0; a < d_; ++a) {
      const auto u = static_cast<std::size_t>(a);
      const double x = static_cast<double>(point[a]);
      if (q[u] - r > 0) {
        left = true;
        beyond = std::min(beyond, x - edge(a, q[u] - r));
      }
      if (q[u] + r < buckets_[u] - 1) {
        left = true;
        beyond = std::min(beyond, edge(a, q[u] + r + 1) - x);
      }
    }
    if (!left) break;
    beyond -= margin_;
    // Strictly farther than the best, with room for the rounding of the reference distance: no
    // centroid left can beat or tie it.
    if (best >= 0 && beyond > 0 && beyond * beyond * (1 - 1e-12) > best_squared) break;
  }
  if (distance) *distance = best_squared;
  return best;
}

}  // namespace qdmeta
