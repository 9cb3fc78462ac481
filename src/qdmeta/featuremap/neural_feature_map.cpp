#include "qdmeta/featuremap/neural_feature_map.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "qdmeta/core/params.hpp"
#include "qdmeta/featuremap/network_kernel.hpp"

namespace qdmeta {
void transpose_rows(const Real* rows, Index count, Index cols, Real* out, Index ld) {
  Index k = 0;
#if defined(__AVX2__)
  // 8 x 8 tiles in registers: eight row loads, a shuffle network, eight column stores.
  const Index whole_rows = count - count % 8;
  for (; k + 8 <= cols; k += 8) {
    for (Index r = 0; r < whole_rows; r += 8) {
      const Real* in = rows + r * cols + k;
      __m256 a0 = _mm256_loadu_ps(in), a1 = _mm256_loadu_ps(in + cols), a2 = _mm256_loadu_ps(in + 2 * cols),
             a3 = _mm256_loadu_ps(in + 3 * cols), a4 = _mm256_loadu_ps(in + 4 * cols),
             a5 = _mm256_loadu_ps(in + 5 * cols), a6 = _mm256_loadu_ps(in + 6 * cols),
             a7 = _mm256_loadu_ps(in + 7 * cols);
      const __m256 t0 = _mm256_unpacklo_ps(a0, a1), t1 = _mm256_unpackhi_ps(a0, a1);
      const __m256 t2 = _mm256_unpacklo_ps(a2, a3), t3 = _mm256_unpackhi_ps(a2, a3);
      const __m256 t4 = _mm256_unpacklo_ps(a4, a5), t5 = _mm256_unpackhi_ps(a4, a5);
      const __m256 t6 = _mm256_unpacklo_ps(a6, a7), t7 = _mm256_unpackhi_ps(a6, a7);
      const __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xEE);
      const __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xEE);
      const __m256 u4 = _mm256_shuffle_ps(t4, t6, 0x44), u5 = _mm256_shuffle_ps(t4, t6, 0xEE);
      const __m256 u6 = _mm256_shuffle_ps(t5, t7, 0x44), u7 = _mm256_shuffle_ps(t5, t7, 0xEE);
      Real* o = out + k * ld + r;
      _mm256_storeu_ps(o, _mm256_permute2f128_ps(u0, u4, 0x20));
      _mm256_storeu_ps(o + ld, _mm256_permute2f128_ps(u1, u5, 0x20));
      _mm256_storeu_ps(o + 2 * ld, _mm256_permute2f128_ps(u2, u6, 0x20));
      _mm256_storeu_ps(o + 3 * ld, _mm256_permute2f128_ps(u3, u7, 0x20));
      _mm256_storeu_ps(o + 4 * ld, _mm256_permute2f128_ps(u0, u4, 0x31));
      _mm256_storeu_ps(o + 5 * ld, _mm256_permute2f128_ps(u1, u5, 0x31));
      _mm256_storeu_ps(o + 6 * ld, _mm256_permute2f128_ps(u2, u6, 0x31));
      _mm256_storeu_ps(o + 7 * ld, _mm256_permute2f128_ps(u3, u7, 0x31));
    }
    for (Index kk = k; kk < k + 8; ++kk)  // the last count % 8 rows
      for (Index r = whole_rows; r < count; ++r) out[kk * ld + r] = rows[r * cols + kk];
  }
#endif
  for (; k < cols; ++k) {  // columns left over (all of them without AVX2)
    Real* __restrict col = out + k * ld;
    const Real* __restrict in = rows + k;
    for (Index r = 0; r < count; ++r) col[r] = in[r * cols];
  }
}

void NeuralFeatureMapShape::validate() const {
  require_at_least("feature-map inputs (base features)", inputs, Index{1});
  require_at_least("feature_map.hidden", hidden, Index{1});
  require_at_least("feature-map outputs (target features)", outputs, Index{1});
  if (!(alpha > 0.0) || !std::isfinite(alpha))
    throw InputError(fmt::format("feature_map.alpha = {} is out of range: must be finite and above 0", alpha));
}

NeuralFeatureMap::NeuralFeatureMap(NeuralFeatureMapShape shape, std::span<const double> weights)
    : shape_(shape) {
  shape_.validate();
  const Index k = shape_.weight_count();
  if (static_cast<Index>(weights.size()) != k)
    throw InputError(fmt::format(
        "neural feature-map: got {} weights, but {} inputs, {} hidden units and {} outputs need K = {}*{} + 1 + {}*{} + 1 = {}",
        weights.size(), shape_.inputs, shape_.hidden, shape_.outputs, shape_.hidden, shape_.inputs,
        shape_.outputs, shape_.hidden, k));
  for (std::size_t i = 0; i < weights.size(); ++i)
    if (!std::isfinite(weights[i]))
      throw InputError(fmt::format("neural feature-map: weight {} is {}: must be finite", i, weights[i]));
  const auto n1 = static_cast<std::size_t>(shape_.hidden * shape_.inputs);
  const auto n2 = static_cast<std::size_t>(shape_.outputs * shape_.hidden);
  // S_N(x) = 1 / (1 + 2^(-alpha log2(e) x / (N + 1))): the factor goes into the weights.
  const double log2e = 1.4426950408889634;
  const double c1 = -shape_.alpha * log2e / static_cast<double>(shape_.inputs + 1);
  const double c2 = -shape_.alpha * log2e / static_cast<double>(shape_.hidden + 1);
  const auto scaled = [](double w, double c) { return static_cast<Real>(w * c); };
  w1_.resize(n1);
  for (std::size_t i = 0; i < n1; ++i) w1_[i] = scaled(weights[i], c1);
  b1_ = scaled(weights[n1], c1);
  w2_.resize(n2);
  for (std::size_t i = 0; i < n2; ++i) w2_[i] = scaled(weights[n1 + 1 + i], c2);
  b2_ = scaled(weights[n1 + 1 + n2], c2);
}

void NeuralFeatureMap::map_transposed(const Real* base_t, Index base_ld, Index count, Real* target_t,
                                      Index target_ld, BaseRows rows) const {
  const NetworkView net{w1_.data(), w2_.data(), shape_.inputs, shape_.hidden, shape_.outputs, b1_, b2_};
  run_network_t(net, base_t, base_ld, count, target_t, target_ld, rows);
}

void NeuralFeatureMap::map(const Real* base, Index count, Real* target) const {
  if (count <= 0) return;
  const Index nb = shape_.inputs;
  const Index nt = shape_.outputs;
  const Index block = padded_rows(std::min(count, kBlockRows));
  // Zeroed once, so the padding columns of a partial last block stay finite.
  std::vector<Real> buffer(static_cast<std::size_t>((nb + nt) * block), Real{0});
  Real* base_t = buffer.data();
  Real* target_t = buffer.data() + nb * block;
  for (Index first = 0; first < count; first += block) {
    const Index n = std::min(block, count - first);
    transpose_rows(base + first * nb, n, nb, base_t, block);
    map_transposed(base_t, block, n, target_t, block);
    Real* out = target + first * nt;
    for (Index t = 0; t < nt; ++t)
      for (Index r = 0; r < n; ++r) out[r * nt + t] = target_t[t * block + r];
  }
}

}  // namespace qdmeta
