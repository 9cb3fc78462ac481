#include "qdmeta/archive/nearest_centroid.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <utility>
#if defined(__AVX512F__)
#include <immintrin.h>
#endif

#include "qdmeta/archive/centroid_values.hpp"
#include "qdmeta/archive/fast_distance.hpp"
#include "qdmeta/archive/list_selection.hpp"
#include "qdmeta/archive/reference_distance.hpp"
#include "qdmeta/core/error.hpp"

namespace qdmeta {
namespace {

// Neighbour lists: the threshold comes from every kSampleStep-th value.
constexpr Index kSampleStep = 64;

// The indices j < k with values[j] <= threshold, in increasing order, into `out` (k + 16
// long); returns how many. Branch-free (which values pass is random): a compress of 16 indices
// per instruction where the machine has one, else one store per value. The same indices
// either way.
std::size_t indices_at_most(const Real* values, Index k, Real threshold, std::int32_t* out) {
  std::size_t n = 0;
  Index j = 0;
#if defined(__AVX512F__)
  const __m512 t = _mm512_set1_ps(threshold);
  __m512i index = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (; j + 16 <= k; j += 16) {
    const __mmask16 mask = _mm512_cmp_ps_mask(_mm512_loadu_ps(values + j), t, _CMP_LE_OQ);
    _mm512_storeu_si512(out + n, _mm512_maskz_compress_epi32(mask, index));
    n += static_cast<std::size_t>(std::popcount(static_cast<unsigned>(mask)));
    index = _mm512_add_epi32(index, _mm512_set1_epi32(16));
  }
#endif
  for (; j < k; ++j) {
    out[n] = static_cast<std::int32_t>(j);
    n += values[j] <= threshold;
  }
  return n;
}

// The smallest of k values (NaN never is).
Real min_value(const Real* values, Index k) {
  using Lanes = Real __attribute__((vector_size(16 * sizeof(Real))));
  constexpr Real kInf = std::numeric_limits<Real>::infinity();
  Lanes lowest = {kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf, kInf};
  Index j = 0;
  for (; j + 16 <= k; j += 16) {
    Lanes v;
    std::memcpy(&v, values + j, sizeof v);
    lowest = v < lowest ? v : lowest;
  }
  Real best = kInf;
  for (int i = 0; i < 16; ++i) best = lowest[i] < best ? lowest[i] : best;
  for (; j < k; ++j) best = values[j] < best ? values[j] : best;
  return best;
}

struct NeighbourScratch {
  std::vector<Real> values, sample;
  std::vector<std::uint64_t> keys, chosen, scratch;
  std::vector<std::int32_t> passed;
};

}  // namespace

double squared_distance(const Real* a, const Real* b, Index dimensions) {
  return reference_squared_distance(a, b, dimensions);
}

Index nearest_centroid_naive(const RowMatrix& centroids, const Real* point) {
  Index best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (Index c = 0; c < centroids.rows(); ++c) {
    const double d = squared_distance(point, centroids.row(c).data(), centroids.cols());
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

NearestCentroid::NearestCentroid(RowMatrix centroids) : centroids_(std::move(centroids)) {
  if (centroids_.rows() < 1 || centroids_.cols() < 1)
    throw InputError(fmt::format("nearest centroid: {} x {} centroids: need at least one centroid of one dimension",
                                 centroids_.rows(), centroids_.cols()));
  if (!centroids_.allFinite()) throw InputError("nearest centroid: a centroid has a NaN or infinite coordinate");
  norms_ = centroids_.rowwise().squaredNorm();
  const Index k = centroids_.rows(), d = centroids_.cols(), padded = padded_centroids(k);
  blocked_.assign(static_cast<std::size_t>(padded * d), 0.0f);
  padded_norms_.assign(static_cast<std::size_t>(padded), 0.0f);
  for (Index c = 0; c < k; ++c) {
    padded_norms_[static_cast<std::size_t>(c)] = norms_[c];
    for (Index i = 0; i < d; ++i)
      blocked_[static_cast<std::size_t>(((c / kValueLanes) * d + i) * kValueLanes + c % kValueLanes)] = -2 * centroids_(c, i);  // exact scaling
  }
  max_norm_ = std::sqrt(static_cast<double>(norms_.maxCoeff()));
  if (d <= CentroidGrid::kMaxDimensions) grid_.emplace(centroids_);
}

Index NearestCentroid::find(const Real* point) const {
  Index cell = 0;
  find(point, 1, &cell);
  return cell;
}

void NearestCentroid::neighbours(const Real* points, Index rows, Index count, std::int32_t* cells, float* distances,
                                 double* outside) const {
  // Per-thread scratch: allocating its k-long buffers for each remake cost more than the
  // selection itself.
  thread_local NeighbourScratch s;
  const Index padded = padded_centroids(this->count()), d = dimensions();
  s.values.resize(static_cast<std::size_t>(kValueRows * padded));
  for (Index first = 0; first < rows; first += kValueRows) {
    const Index n = std::min(kValueRows, rows - first);
    centroid_values(points + first * d, n, blocked_.data(), padded_norms_.data(), padded, d, s.values.data());
    for (Index r = 0; r < n; ++r) {
      const Index row = first + r;
      select_list(points + row * d, s.values.data() + r * padded, count, cells + row * count, distances + row * count,
                  outside + row);
    }
  }
}

void NearestCentroid::select_list(const Real* point, const Real* values, Index count, std::int32_t* cells,
                                  float* distances, double* outside) const {
  thread_local NeighbourScratch s;
  const Index k = this->count(), d = dimensions();
  std::vector<std::uint64_t>& keys = s.keys;
  std::vector<std::uint64_t>& chosen = s.chosen;
  keys.clear();
  // A centroid's exact squared distance is ||x||^2 plus its exact value, which lies within the
  // value's rounding bound (as in find()) of the float one: a lower bound on the distance.
  const Eigen::Map<const Vector> x(point, d);
  const double reach = std::sqrt(static_cast<double>(x.squaredNorm())) + max_norm_;
  const double error = 4.0 * (static_cast<double>(d) + 1.0) * (std::numeric_limits<Real>::epsilon() / 2) * reach * reach;
  double norm = 0.0;
  for (Index i = 0; i < d; ++i) norm += static_cast<double>(point[i]) * point[i];
  const auto lower_distance = [&](Real value) {
    const double squared = norm + static_cast<double>(value) - error;
    return squared > 0 ? std::sqrt(squared) : 0.0;
  };
  if (count < k) {
    // The `count` smallest values (ties to the lowest index). A threshold from every 64th value,
    // set to let through about twice `count`, keeps one cheap pass over all values and a
    // selection among the few that pass; when too few pass, the selection runs over all values.
    std::vector<Real>& sample = s.sample;
    sample.clear();
    for (Index j = 0; j < k; j += kSampleStep) sample.push_back(values[j]);
    const auto q = std::min<std::size_t>(sample.size() - 1, static_cast<std::size_t>(2 * count / kSampleStep + 2));
    std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(q), sample.end());
    const Real threshold = sample[q];
    std::vector<std::int32_t>& passed = s.passed;
    passed.resize(static_cast<std::size_t>(k + 16));
    keys.resize(indices_at_most(values, k, threshold, passed.data()));
    for (std::size_t i = 0; i < keys.size(); ++i) keys[i] = value_key(values[passed[i]], passed[i]);
    if (static_cast<Index>(keys.size()) <= count) {  // rare: select among all values
      keys.clear();
      for (Index j = 0; j < k; ++j) keys.push_back(value_key(values[j], j));
    }
    // The smallest value left out: the values that did not pass exceed every one that did.
    // Every centroid outside the list has a float value at least `next`.
    const Real next = key_value(select_smallest(keys, count, chosen, s.scratch));
    *outside = lower_distance(next) * (1 - 1e-9);
  } else {
    chosen.clear();
    for (Index j = 0; j < k; ++j) chosen.push_back(value_key(values[j], j));
    *outside = std::numeric_limits<double>::infinity();
  }
  // The listed centroids (in index order) sorted by value; the sort is stable, so ties go to
  // the lowest index. Their listed distances are the lower bounds their values give (monotone
  // in the value, so sorted too; rounded to float, within the 1e-6 the walks allow for):
  // below the exact distance by at most about error / (2 distance), under 1e-4 for the paper's
  // [0,1]^20 (against deltas of 0.05 to 0.2 in a walk's bounds), where exact distances would
  // read `count` scattered centroid rows.
  sort_by_value(chosen, s.scratch);
  for (Index i = 0; i < count; ++i) {
    const std::uint64_t key = chosen[static_cast<std::size_t>(i)];
    cells[i] = key_index(key);
    distances[i] = static_cast<float>(lower_distance(key_value(key)) * (1 - 1e-9));
  }
}

void NearestCentroid::find(const Real* points, Index n, Index* cells, double* distances) const {
  if (!grid_) {
    find_by_product(points, n, cells, distances);
    return;
  }
  const Index d = dimensions();
  for (Index r = 0; r < n; ++r) {
    double distance = 0.0;
    const Index cell = grid_->find(points + r * d, &distance);
    if (cell < 0) throw Error(fmt::format("nearest centroid: point {} has a NaN or infinite coordinate", r));
    cells[r] = cell;
    if (distances) distances[r] = distance;
  }
}

void NearestCentroid::find_by_product(const Real* points, Index n, Index* cells, double* distances) const {
  // The values of kValueRows points at a time (centroid_values), the smallest, then the exact
  // reference distance for every centroid whose value lies within the rounding bound of it.
  // Rounding bound of one float value ||c||^2 - 2 x.c in any summation order: the norm (d
  // terms) and the d + 1 terms of the sum each add at most about d unit roundoffs times their
  // magnitudes, under (2d + 1) u (||x|| + ||c||)^2 in all. Two values whose exact order could
  // differ lie within twice that; the slack doubles it again for safety. (Faster than Eigen's
  // packed product at every size measured, bench/README.md: no packing of the operands.)
  const Index k = count(), d = dimensions(), padded = padded_centroids(k);
  const double unit = std::numeric_limits<Real>::epsilon() / 2;
  thread_local std::vector<Real> values;
  thread_local std::vector<std::int32_t> candidates;
  values.resize(static_cast<std::size_t>(kValueRows * padded));
  candidates.resize(static_cast<std::size_t>(k + 16));
  for (Index first = 0; first < n; first += kValueRows) {
    const Index rows = std::min(kValueRows, n - first);
    centroid_values(points + first * d, rows, blocked_.data(), padded_norms_.data(), padded, d, values.data());
    for (Index r = 0; r < rows; ++r) {
      const Real* row = values.data() + r * padded;
      const Real* p = points + (first + r) * d;
      const double reach = std::sqrt(static_cast<double>(Eigen::Map<const Vector>(p, d).squaredNorm())) + max_norm_;
      const auto slack = static_cast<Real>(8.0 * (static_cast<double>(d) + 1.0) * unit * reach * reach + 1e-30);
      const std::size_t m = indices_at_most(row, k, min_value(row, k) + slack, candidates.data());
      Index winner = -1;
      double winner_distance = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < m; ++i) {  // in increasing cell order
        const double dist = squared_distance(p, centroids_.row(candidates[i]).data(), d);
        if (dist < winner_distance) {
          winner_distance = dist;
          winner = candidates[i];
        }
      }
      if (winner < 0) throw Error(fmt::format("nearest centroid: point {} has a NaN or infinite coordinate", first + r));
      cells[first + r] = winner;
      if (distances) distances[first + r] = winner_distance;
    }
  }
}

}  // namespace qdmeta
